"""Which component made a simulation fail, and how: the error path of the compiled kernels.

A composition's hooks run inside one compiled right-hand side. When a hook raises, numba
reports the kernel, not the hook (from the parallel batch only ``SystemError: CPUDispatcher(...)
returned a result with an exception set``); when a hook cannot be compiled, numba reports a
page of typing trace through the generated kernel; when a hook yields NaN, the integrator only
sees a non-finite state. On that path, and only there, the failing stretch is replayed with the
kernel module run as plain Python and every hook called on its own (the same compiled hook, so
the same arithmetic; its plain-Python ``py_func`` when compilation is off). The first hook that
raises, or that turns finite totals non-finite in the interval that failed, is named with its
own error: :class:`~pneumatic_servo.errors.EffectError`, one line.

Nothing here runs unless a kernel has already failed.
"""
from __future__ import annotations

import math
import time
from pathlib import Path

import numpy as np

from .. import _jit
from ..effects.base import STAGES
from ..effects.layout import CORE_STATE_NAMES, OUTPUTS
from ..errors import EffectError, PneumaticServoError
from . import kernel_cache

#: kernels whose failures are explained (a composition's right-hand side and the integrators)
KERNELS = ('rhs', 'fixed_interval', 'adaptive_interval', 'run', 'run_batch')
#: the integrators' source (not imported here: importing compiles them)
_STEPPING = Path(__file__).with_name('stepping.py')
#: the lines importing the compiler in the replayed sources, and what replaces them
_JIT_IMPORTS = ('from pneumatic_servo._jit import njit\n',)
_PLAIN = 'njit = lambda *a, **k: (lambda f: f)\n'
#: [s] wall-clock budget of one replay; it stops there and names nobody
REPLAY_BUDGET_S = 60.0
#: samples replayed after the last recorded one before the failure counts as not reproduced
REPLAY_SAMPLES = 200
_MATH_ERRORS = (ValueError, ZeroDivisionError, OverflowError)


class _Raised(Exception):
    """A hook raised in the replay: stops it there."""

    def __init__(self, fault: 'Fault'):
        super().__init__(fault)
        self.fault = fault


class _Budget(Exception):
    """The replay ran out of time."""


class Fault:
    """One hook's failure: which component, which stage, at what time and state, and why."""

    def __init__(self, cls, stage: str, t: float, x: np.ndarray, exc: BaseException | None):
        self.cls, self.stage, self.t, self.x, self.exc = cls, stage, float(t), x.copy(), exc

    @property
    def users(self) -> bool:
        """Whether the component is a user's (not one of this package's)."""
        return not (self.cls.__module__ or '').startswith('pneumatic_servo.')

    def describe(self, t_offset: float = 0.0) -> str:
        cls = self.cls
        kind = 'effect' if cls.slot is None else 'component'
        if self.users:
            source = getattr(cls, 'source', None) or f'{cls.__module__}.{cls.__qualname__}'
            who = f'{kind} {cls.name!r} ({source})'
        else:
            who = f'{kind} {cls.name!r}'
        when = f't = {self.t + t_offset:.6g} s'
        state = ', '.join(f'{name} {self.x[i]:.6g}' for i, name in
                          enumerate(CORE_STATE_NAMES[:4]))
        exc = self.exc
        if exc is None:
            fix = ('its hook must give finite values over the whole stroke and pressure range '
                   '(guard divisions, square roots and powers)' if self.users else
                   'check its parameter values')
            return f'{who} gave NaN or inf in its {self.stage} hook at {when} ({state}); {fix}'
        if type(exc).__module__.startswith('numba'):
            return (f'{who}: its {self.stage} hook cannot be compiled by numba '
                    f'({_numba_reason(exc)}); use only numbers, numpy arrays and math in a hook '
                    '(or run it uncompiled with PNEUMATIC_SERVO_JIT=0)')
        text = ' '.join(str(exc).split()) or 'no message'
        return (f'{who} raised {type(exc).__name__} in its {self.stage} hook at {when} '
                f'({state}): {text}; fix the effect or leave it out')


def _numba_reason(exc) -> str:
    """The line of a numba error that says what is wrong (not the trace through the kernel)."""
    lines = [ln.strip() for ln in str(exc).splitlines() if ln.strip()]
    for line in lines:
        if not line.startswith(('Failed in ', 'During:')):
            return line[:200]
    return type(exc).__name__


# --------------------------------------------------------------------------- the replay
_MODULES: dict[tuple, dict] = {}


class _Tracer:
    """Calls each hook on its own and keeps what it saw."""

    def __init__(self):
        self.events: list[Fault] = []   # hooks that turned finite totals non-finite
        self.deadline = math.inf

    def hook(self, cls, stage: str, fn):
        compiled = _jit.ENABLED and hasattr(fn, 'py_func')

        def traced(t, x, s, p, P, c, dx):
            if time.perf_counter() > self.deadline:
                raise _Budget()
            finite = np.isfinite(c).all() and np.isfinite(dx).all()
            try:
                fn(t, x, s, p, P, c, dx)
            except (_Raised, _Budget):
                raise
            except _MATH_ERRORS as exc:
                if compiled:
                    raise _Raised(Fault(cls, stage, t, x, exc)) from None
                # plain Python raises where compiled code gives NaN; the run turns it into NaN
                self.events.append(Fault(cls, stage, t, x, exc))
                raise
            except Exception as exc:
                raise _Raised(Fault(cls, stage, t, x, exc)) from None
            if finite and not (np.isfinite(c).all() and np.isfinite(dx).all()):
                self.events.append(Fault(cls, stage, t, x, None))
        return traced


def _module(layout) -> dict:
    """The composition's right-hand side and the integrators (:mod:`.stepping`) as plain
    Python (their source, uncompiled), in one namespace."""
    if layout.classes not in _MODULES:
        namespace = {'__name__': 'pneumatic_servo_kernel_replay'}
        for source in (kernel_cache.module_source(layout),
                       _STEPPING.read_text()):
            if not any(line in source for line in _JIT_IMPORTS):  # changed: no replay
                return {}
            for line in _JIT_IMPORTS:
                source = source.replace(line, _PLAIN)
            exec(compile(source, '<kernel replay>', 'exec'), namespace)
        _MODULES[layout.classes] = namespace
    return _MODULES[layout.classes]


def _replay(layout, name: str, args: tuple):
    """Run kernel ``name`` on ``args`` (copied) in plain Python with every hook traced.

    Returns (Fault or None, status or None)."""
    module = _module(layout)
    if not module:
        return None, None
    tracer = _Tracer()
    for i, cls in enumerate(layout.classes):
        for stage in STAGES:
            fn = cls.hook(stage)
            if fn is not None:
                module[f'_hook_{i}_{stage}'] = tracer.hook(cls, stage, fn)
    args = tuple(a.copy() if isinstance(a, np.ndarray) else a for a in args)
    tracer.deadline = time.perf_counter() + REPLAY_BUDGET_S
    try:
        result = (module['rhs'](*args) if name == 'rhs' else
                  module[name](module['rhs'], *args))
    except _Raised as found:
        return found.fault, None
    except Exception:  # the core failed, or the replay ran out of time: name nobody
        return None, None
    status = result[0] if isinstance(result, tuple) else result
    if status != 0 and tracer.events:
        return tracer.events[-1], status
    return None, status


def _last_recorded(X: np.ndarray) -> int:
    """Index of the last sample a run recorded (rows filled with NaN beforehand), or -1."""
    done = np.isfinite(X).all(axis=1)
    if not done[0]:
        return -1
    bad = np.flatnonzero(~done)
    return int(bad[0]) - 1 if len(bad) else len(X) - 1


def replay_run(layout, x0, t, u, ps, P, circuit, adaptive, rtol, atol, n_sub,
               X: np.ndarray | None = None):
    """The fault of a failed ``run`` (its ``X`` filled with NaN beforehand, so that the
    recorded samples show where it stopped): replayed from the last recorded sample."""
    k = _last_recorded(X) if X is not None else -1
    if k < 0:
        k, x = 0, np.asarray(x0, float)
    else:
        x = X[k]
    stop = min(len(t), k + 1 + REPLAY_SAMPLES)
    if stop - k < 2:
        return None
    Xr = np.full((stop - k, len(x)), np.nan)
    Yr = np.full((stop - k, len(OUTPUTS)), np.nan)
    fault, _ = _replay(layout, 'run', (np.asarray(x, float), t[k:stop], u[k:stop], ps[k:stop],
                                      P, circuit, adaptive, rtol, atol, n_sub, Xr, Yr))
    return fault


def failure(layout, kernels: dict, name: str, args: tuple, exc: BaseException,
            t_offset: float = 0.0):
    """An :class:`EffectError` naming the hook behind ``exc`` (raised by kernel ``name``
    called with ``args``), or None when no component's hook is to blame (a bug of the
    package's: the caller re-raises)."""
    if isinstance(exc, PneumaticServoError):
        return None
    if name == 'run_batch':
        X0, t, U, PS, PM, circuit, adaptive, rtol, atol, n_sub = args[:10]
        run = kernels['run']
        for m in range(PM.shape[0]):  # one row at a time: which one raises
            X = np.full((len(t), X0.shape[1]), np.nan)
            Y = np.full((len(t), args[11].shape[2]), np.nan)
            try:
                run(X0[m], t, U[m], PS[m], PM[m], circuit, adaptive, rtol, atol, n_sub, X, Y)
            except Exception:
                fault = replay_run(layout, X0[m], t, U[m], PS[m], PM[m], circuit, adaptive,
                                   rtol, atol, n_sub, X)
                return _error(fault, t_offset)
        return None
    if name == 'run':
        return _error(replay_run(layout, *args[:11]), t_offset)  # X shows where it stopped
    if name == 'adaptive_interval':  # its first derivative is the caller's; recompute it
        t, x, u, ps, P, circuit = args[:6]
        w = args[11].copy()
        fault, _ = _replay(layout, 'rhs', (t, x, u, ps, P, circuit, args[10], w[0]))
        if fault is None:
            fault, _ = _replay(layout, name, args[:11] + (w,) + args[12:])
        return _error(fault, t_offset)
    fault, _ = _replay(layout, name, args)
    return _error(fault, t_offset)


def _error(fault: Fault | None, t_offset: float):
    if fault is None:
        return None
    if fault.exc is not None and not fault.users:
        return None  # the package's own hook raised: a bug to report, not the user's to fix
    return EffectError(fault.describe(t_offset))


def explain_status(layout, x0, t, u, ps, P, circuit, adaptive, rtol, atol, n_sub,
                   X: np.ndarray | None = None, t_offset: float = 0.0) -> str:
    """'' or ': ' + which hook made a run end with a failed status (non-finite state, step
    collapse), found by replaying it from its last recorded sample."""
    try:
        fault = replay_run(layout, x0, t, u, ps, P, circuit, adaptive, rtol, atol, n_sub, X)
    except Exception:  # the error path must not raise an error of its own
        return ''
    return f': {fault.describe(t_offset)}' if fault is not None else ''


def guarded(layout, kernels: dict) -> dict:
    """``kernels`` with each call guarded: an exception raised inside becomes the
    :class:`EffectError` of the hook that raised it (or is re-raised as it is)."""
    out = dict(kernels)
    for name in KERNELS:
        if name in kernels:
            out[name] = Guarded(layout, kernels, name)
    return out


class Guarded:
    """A kernel that names the failing hook when it raises; otherwise the kernel itself
    (attributes such as numba's ``stats`` and ``py_func`` are the kernel's)."""

    def __init__(self, layout, kernels: dict, name: str):
        self.kernel = kernels[name]
        self._layout, self._kernels, self.__name__ = layout, kernels, name
        self.__doc__ = self.kernel.__doc__

    def __call__(self, *args):
        try:
            return self.kernel(*args)
        except Exception as exc:
            try:
                error = failure(self._layout, self._kernels, self.__name__, args, exc)
            except Exception:  # explaining must never hide the original error
                error = None
            if error is None:
                raise
            raise error from exc

    def __getattr__(self, attr):
        return getattr(self.kernel, attr)
