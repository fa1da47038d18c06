"""Lines from a child process's pipe, each awaited at most a given time.

Why not ``select`` and then ``readline``: a buffered reader can take two lines from the
pipe at once, and a ``select`` on the descriptor then waits for a line the buffer already
holds (until the child writes again, or ends). This reads the descriptor itself and keeps
its own buffer.
"""
from __future__ import annotations

import os
import select
import time


class PipeLines:
    """``next(timeout)``: the next line of ``pipe`` (a binary or text pipe of a
    ``subprocess.Popen``), decoded as UTF-8 and without its newline."""

    def __init__(self, pipe):
        self._fd = pipe.fileno()
        self._held = b''  # read from the pipe and not yet returned

    def next(self, timeout: float) -> str | None:
        """The next line; ``''`` once the pipe has ended, ``None`` if no whole line came
        within ``timeout`` seconds."""
        deadline = time.monotonic() + timeout
        while b'\n' not in self._held:
            left = deadline - time.monotonic()
            if left <= 0 or not select.select([self._fd], [], [], left)[0]:
                return None
            chunk = os.read(self._fd, 4096)
            if not chunk:  # ended: a last line without its newline is still a line
                line, self._held = self._held, b''
                return line.decode()
            self._held += chunk
        line, self._held = self._held.split(b'\n', 1)
        return line.decode()
