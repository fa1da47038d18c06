"""Optional numba compilation.

The model runs as plain Python when numba is absent or when
``PNEUMATIC_SERVO_JIT=0``; the same source is compiled when numba is present.
"""
import os

try:  # numba is a speed-up, never a requirement
    import numba as _numba
except ImportError:  # pragma: no cover - exercised where numba is absent
    _numba = None

ENABLED = _numba is not None and os.environ.get('PNEUMATIC_SERVO_JIT', '1') != '0'


def njit(func=None, **options):
    """Compile ``func`` with numba in nopython mode when available, else return it."""
    def wrap(f):
        if not ENABLED:
            return f
        return _numba.njit(fastmath=False, **options)(f)
    return wrap(func) if func is not None else wrap


#: ``numba.prange`` when compiling (parallel loops), ``range`` otherwise
prange = _numba.prange if ENABLED else range


def is_compiled(func) -> bool:
    """True if ``func`` is already a numba dispatcher (or compilation is off)."""
    return not ENABLED or hasattr(func, 'py_func')
