"""Compile each composition of components once per machine, not once per process.

The right-hand side of a composition calls the components' stage hooks in a fixed order
with their parameter slices and state offsets as constants. It is written out as the
source of a small module (``kernel_template.py`` with its composition block filled in),
whose functions numba caches on disk (``cache=True``); the integrators that call it are
compiled once for all compositions (:mod:`.stepping`). A second process with the same
composition, a Dask worker or a node restart, loads the machine code instead of spending
seconds compiling it again.

The module's file name is a hash of everything its machine code depends on: the source
of this package and of every component's module, the composition, and the numba and
Python versions. A changed hook therefore gets a new file; numba's own staleness check
(the file's time stamp) is never relied on. The cache lives in ``$PNEUMATIC_SERVO_CACHE``,
or ``~/.cache/pneumatic_servo/kernels``; if that cannot be written, a private temporary
directory is used, which still works but does not persist.
"""
from __future__ import annotations

import hashlib
import inspect
from functools import lru_cache, partial
from pathlib import Path

from .. import _jit
from ..effects.base import STAGES, switched

_PACKAGE = Path(__file__).resolve().parents[1]
_TEMPLATE = Path(__file__).with_name('kernel_template.py')
_BEGIN, _END = '# COMPOSITION BEGIN\n', '# COMPOSITION END\n'


@lru_cache(maxsize=1)
def _package_digest() -> str:
    """Hash of this package's source: any edit gives every composition a new module."""
    h = hashlib.sha256()
    for path in sorted(_PACKAGE.rglob('*.py')):
        h.update(str(path.relative_to(_PACKAGE)).encode())
        h.update(path.read_bytes())
    return h.hexdigest()


def _source_of(cls) -> bytes:
    """Source text of the module defining ``cls`` (a user's file or the package's)."""
    try:
        return Path(inspect.getsourcefile(cls)).read_bytes()
    except (TypeError, OSError):  # defined interactively: key by its identity instead
        return repr(id(cls)).encode()


def _switched_on(cls, p1: int) -> str:
    """The condition under which component ``cls`` (its slice of ``P`` ending before ``p1``)
    is called: '' (always) unless it is ``skipped_at_neutral`` and stateless: then while its
    switch is on (the slice's last entry, :func:`..effects.base.switched`: a parameter differs
    from its neutral value, at which it adds exactly nothing).
    """
    return '' if cls.states or not switched(cls) else f'P[{p1 - 1}] != 0.0'


def module_source(layout) -> str:
    """Source of the kernel module of ``layout``: the template with its composition."""
    lines = []
    for stage in STAGES:
        calls = []
        for i in layout.hook_order():
            if layout.classes[i].hook(stage) is not None:
                p0, p1 = layout.param_slices[i]
                call = (f'_hook_{i}_{stage}(t, x, {layout.state_offsets[i]}, '
                        f'P[{p0}:{p1}], P, c, dx)')
                switched_on = _switched_on(layout.classes[i], p1)
                calls += ([f'    if {switched_on}:', f'        {call}'] if switched_on
                          else [f'    {call}'])
        lines += ['@njit(cache=True, allocates=False)', f'def _{stage}(t, x, P, c, dx):',
                  *(calls or ['    pass']), '', '']
    lines += ['@njit(cache=True, allocates=False)', 'def _rhs(t, x, u, ps, P, circuit, c, dx):',
              '    core_begin(t, x, u, ps, P, circuit, c, dx)',
              *(f'    _{stage}(t, x, P, c, dx)' for stage in STAGES),
              '    core_end(t, x, P, circuit, c, dx)', '', '',
              'rhs = _rhs if ENABLED else nan_on_math_error(_rhs)', '']
    header = ('from pneumatic_servo._jit import ENABLED\n'
              'from pneumatic_servo._jit import njit\n'
              'from pneumatic_servo.model.core import core_begin, core_end, nan_on_math_error\n')
    template = _TEMPLATE.read_text()
    before, rest = template.split(_BEGIN)
    _, after = rest.split(_END)
    return before + header + '\n\n' + '\n'.join(lines) + after


def _key(layout, source: str) -> str:
    return _jit.source_key(_package_digest(), source,
                           *(f'{cls.__module__}.{cls.__qualname__}' for cls in layout.classes),
                           *(_source_of(cls) for cls in layout.classes))


def module_name(layout) -> str:
    """The name of ``layout``'s kernel module (a hash of what its machine code depends on)."""
    return f'pneumatic_servo_kernel_{_key(layout, module_source(layout))}'


def on_disk(layout) -> bool:
    """Whether numba holds compiled code of ``layout``'s right-hand side on disk."""
    try:
        return Path(load(layout)['rhs']._cache._cache_file._index_path).exists()
    except AttributeError:  # another numba's internals, or numba off: say not
        return False


def load(layout) -> dict:
    """Kernels of ``layout`` (``rhs``, and the integrators ``fixed_interval``,
    ``adaptive_interval``, ``run``, ``run_batch`` calling it) from its cached module, writing
    the module first if it is new."""
    source = module_source(layout)
    hooks = {f'_hook_{i}_{stage}': cls.hook(stage)  # the hooks, as globals of the module
             for i, cls in enumerate(layout.classes) for stage in STAGES
             if cls.hook(stage) is not None}
    module = _jit.load_generated(module_name(layout), source, hooks)
    return {'rhs': module.rhs, **{name: Integrator(name, module.rhs) for name in
                                  ('fixed_interval', 'adaptive_interval', 'run', 'run_batch')}}


class Integrator:
    """An integrator of :mod:`.stepping` bound to one composition's right-hand side, called
    with the integrator's other arguments. Bound on first use: importing :mod:`.stepping`
    compiles it on a fresh machine, which a process that only compiles a right-hand side (a
    helper of :mod:`.compile_ahead`) never needs.

    A whole run (``run``, ``run_batch``) is called with the right-hand side as its argument:
    numba converts it to a function's address on each call (95 us, measured), nothing
    beside a run. A real-time stepper is called once per control period: there a small
    compiled function holds the right-hand side and converts it once, when it compiles
    (about 1 s per composition in each process that steps it: numba cannot cache code that
    holds a function's address).
    """

    def __init__(self, name: str, rhs):
        self.name, self.rhs, self._bound = name, rhs, None

    def __call__(self, *args):
        return self.bound(*args)

    @property
    def bound(self):
        """The integrator with the right-hand side bound."""
        if self._bound is None:
            from . import stepping
            integrator = getattr(stepping, self.name)
            if self.name == 'run_batch':  # blocks of rows in threads
                self._bound = partial(stepping.run_batch_threaded, self.rhs)
            elif self.name == 'run':
                self._bound = partial(integrator, self.rhs)
            else:
                self._bound = _holding(integrator, self.rhs)
        return self._bound

    def __getattr__(self, attr):  # numba's attributes (``targetoptions``, ...)
        if attr.startswith('_'):  # not yet set (a copy being made): never bind for it
            raise AttributeError(attr)
        return getattr(self.bound, attr)


def _holding(integrator, rhs):
    """``integrator`` with ``rhs`` as its first argument, compiled (a closure: not cached)."""
    @_jit.njit(allocates=False)
    def bound(*args):
        return integrator(rhs, *args)
    return bound
