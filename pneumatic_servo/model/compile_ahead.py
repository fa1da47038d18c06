"""Compile the compositions a long job will need in a helper process, while this one works.

On a fresh machine a diagnosis compiles its compositions' right-hand sides one after
another (1.3-1.7 s each on a 2-core AMD EPYC, 26.5 s for the host of every generic
correction: :mod:`.stepping` holds the integrators, compiled once). The later ones do not
depend on what the earlier ones find, so :func:`start` has a helper process
(:mod:`.compile_helper`) compile some of them into the on-disk cache (:mod:`.kernel_cache`)
while this process compiles and fits the others; when this process reaches one,
:func:`wait` blocks until the helper has finished it, and numba loads it from the cache
instead of compiling it again. Which compositions are handed over is
:func:`.assembly.compile_in_background`'s choice.

If the helper fails or is slow, this process compiles for itself: at worst as slowly as
without it, never wrongly.
"""
from __future__ import annotations

import atexit
import json
import subprocess
import sys
import time

from ..pipes import PipeLines

#: [s] longest wait for the helper to finish one composition before compiling here. Only a
#: hung helper costs it (one that fails ends its output at once); it is long because a slow
#: one is still the fastest way to the code: on a loaded 2-core machine a composition took
#: over 120 s to compile, and a helper stopped then had its work done again here
WAIT_S = 600.0

_helper: subprocess.Popen | None = None
_lines: PipeLines | None = None  # the helper's output: the names it has compiled
_pending: set[str] = set()


def start(jobs: list[tuple[str, dict]]) -> None:
    """Have a helper process compile ``jobs`` (kernel module name, model config as a dict),
    in order; returns at once. One helper at a time: while one runs, this does nothing."""
    global _helper, _lines
    if not jobs or (_helper is not None and _helper.poll() is None):
        return
    try:
        _helper = subprocess.Popen(
            [sys.executable, '-m', 'pneumatic_servo.model.compile_helper'],
            stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
        _helper.stdin.write(json.dumps([config for _, config in jobs]))
        _helper.stdin.close()
        _lines = PipeLines(_helper.stdout)
    except OSError:  # no process to be had: this one compiles
        stop()
        return
    _pending.clear()
    _pending.update(name for name, _ in jobs)


def wait(name: str) -> None:
    """Block until the helper has compiled kernel module ``name``, if it is compiling it (at
    most :data:`WAIT_S`; then it is stopped, and this process compiles)."""
    deadline = time.monotonic() + WAIT_S
    while name in _pending:
        line = _lines.next(max(deadline - time.monotonic(), 0.0))
        if not line:  # the helper ended, failed or took too long
            stop()
            return
        _pending.discard(line.strip())


@atexit.register
def stop() -> None:
    """Stop the helper, if one runs (what it compiled so far stays in the cache)."""
    global _helper, _lines
    if _helper is not None:
        if _helper.poll() is None:
            _helper.kill()
        _helper.wait()
        _helper.stdout.close()
    _helper = _lines = None
    _pending.clear()
