"""Optional numba compilation, and the on-disk home of generated compiled modules.

The model runs as plain Python when numba is absent or when
``PNEUMATIC_SERVO_JIT=0``; the same source is compiled when numba is present.
Generated source (a composition's kernel, the generic corrections' hooks) is written
as a module file under :func:`cache_dir`, so that numba can cache its machine code on
disk (``cache=True`` needs a file) and a second process loads it at once.
"""
import hashlib
import importlib.util
import os
import sys
import tempfile
import warnings
from functools import lru_cache, partial
from pathlib import Path

try:  # numba is a speed-up, never a requirement
    import numba as _numba
except ImportError:  # pragma: no cover - exercised where numba is absent
    _numba = None

ENABLED = _numba is not None and os.environ.get('PNEUMATIC_SERVO_JIT', '1') != '0'
if _numba is not None:
    # the integrators take a right-hand side as a first-class function (model/stepping.py):
    # numba calls that experimental on every compile, which tells a user nothing to act on
    warnings.filterwarnings('ignore', 'First-class function type feature is experimental',
                            _numba.core.errors.NumbaExperimentalFeatureWarning)


def njit(func=None, *, allocates=True, signature=None, **options):
    """Compile ``func`` with numba in nopython mode when available, else return it.

    ``signature`` (numba types, or None when compilation is off): compile at once for
    these argument types only, instead of for each call's types when first called.

    Division follows numpy's rules (``error_model='numpy'``): a division by zero gives an
    infinity or NaN, which the integrators' finiteness checks turn into a failed
    simulation (and :mod:`pneumatic_servo.model.culprit` names the hook), instead of a
    check before every division, which costs a tenth of a simulation (measured).

    ``allocates=False`` declares that ``func`` creates no array (it reads and writes the
    arrays it is given, and may take views of them): it is then compiled without numba's
    reference counting. Every array passed to a compiled function is otherwise counted in
    and out with a locked (atomic) instruction, and the model's right-hand side passes
    its five arrays through a dozen such calls: the counting was four fifths of its cost
    (477 against 103 ns a call, measured on this 2-core machine). A function that does
    allocate fails to compile with the flag, so a wrong declaration is an error, not a
    leak.
    """
    def wrap(f):
        if not ENABLED:
            return f
        flags = {} if allocates else _NO_REFCOUNT
        jit = _numba.njit if signature is None else partial(_numba.njit, signature)
        return jit(fastmath=False, error_model='numpy', **flags, **options)(f)
    return wrap(func) if func is not None else wrap


def _no_refcount_flag() -> dict:
    """numba's option that compiles without its runtime's reference counting (``_nrt``,
    an underscored CPU target option), or nothing on a numba without it."""
    try:
        from numba.core.cpu import CPUTargetOptions
    except ImportError:  # pragma: no cover - a numba with another layout
        return {}
    return {'_nrt': False} if hasattr(CPUTargetOptions, '_nrt') else {}


_NO_REFCOUNT = _no_refcount_flag() if _numba is not None else {}


def is_compiled(func) -> bool:
    """True if ``func`` is already a numba dispatcher (or compilation is off)."""
    return not ENABLED or hasattr(func, 'py_func')


def cache_dir() -> Path:
    """Directory of the generated modules (created; writable or a private temp dir):
    ``$PNEUMATIC_SERVO_CACHE/kernels`` or ``~/.cache/pneumatic_servo/kernels``."""
    root = os.environ.get('PNEUMATIC_SERVO_CACHE') or Path.home() / '.cache' / 'pneumatic_servo'
    path = Path(root) / 'kernels'
    try:
        path.mkdir(parents=True, exist_ok=True)
        probe = tempfile.NamedTemporaryFile(dir=path, prefix='.probe')
        probe.close()
        return path
    except OSError:
        return _private_dir()


@lru_cache(maxsize=1)
def _private_dir() -> Path:
    return Path(tempfile.mkdtemp(prefix='pneumatic_servo_kernels_'))


def load_generated(name: str, source: str, globals_: dict | None = None):
    """Import generated ``source`` as module ``name`` from :func:`cache_dir`, writing the
    file first if it is new (atomically: concurrent writers of one module agree).
    ``globals_`` are set on the module before it runs (functions it calls by name)."""
    path = cache_dir() / f'{name}.py'
    if not path.exists() or path.read_text() != source:
        tmp = path.with_name(f'.{name}.{os.getpid()}.tmp')
        tmp.write_text(source)
        os.replace(tmp, path)
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    for key, value in (globals_ or {}).items():
        setattr(module, key, value)
    sys.modules[name] = module  # so numba and pickling find the module by name
    spec.loader.exec_module(module)
    return module


def source_key(*parts) -> str:
    """A short hash of ``parts`` and of what compiled code depends on (Python, numba, numpy):
    the name of a generated module, so that nothing stale is ever loaded."""
    import numpy
    h = hashlib.sha256()
    for part in (*parts, sys.version, getattr(_numba, '__version__', 'no numba'), ENABLED,
                 numpy.__version__):
        h.update(str(part).encode())
    return h.hexdigest()[:24]
