"""The command line in a process of its own per call, without paying the interpreter's start
each time: a server process imports the package once, then forks a child for every call.

Each child is the command as a user runs it, minus the start-up: its own process, working
directory, stdout and stderr, and exit code, with ``sys.exit(main(argv))``'s semantics (an
uncaught exception prints its traceback and exits 1; the atexit handlers run). Why: the
bad-input suite runs some 80 commands, most of which fail in milliseconds, and on a loaded
2-core machine starting Python and importing numpy, scipy and the verb's modules took 5-8 s
of each.
"""
from __future__ import annotations

import contextlib
import json
import os
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from pneumatic_servo.pipes import PipeLines

SERVER = r'''
import atexit, faulthandler, json, os, signal, sys, traceback
from pneumatic_servo.cli import main
# what the verbs import, imported once here (not the ROS verbs, nor fleet's Dask, whose
# threads a fork would not carry over)
from pneumatic_servo.cli import compare, diagnose, generate, identify, simulate, verify

def child(req):
    os.chdir(req['cwd'])
    for fd, path in ((1, req['out']), (2, req['err'])):
        os.dup2(os.open(path, os.O_WRONLY | os.O_CREAT | os.O_TRUNC), fd)
    os.dup2(os.open(os.devnull, os.O_RDONLY), 0)
    # a call that overruns its time is asked for its stacks before it is killed
    faulthandler.register(signal.SIGUSR1, all_threads=True)
    sys.argv = ['-c', *req['argv']]
    try:
        code = main(req['argv'])
    except SystemExit as exc:
        code = exc.code
    except BaseException:
        traceback.print_exc()
        code = 1
    if code is not None and not isinstance(code, int):
        print(code, file=sys.stderr)
        code = 1
    atexit._run_exitfuncs()
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit((code or 0) & 0xFF)

for line in sys.stdin:
    req = json.loads(line)
    sys.stdout.flush()
    pid = os.fork()
    if pid == 0:
        try:
            child(req)
        finally:  # never back into this loop, whatever went wrong before main
            os._exit(70)
    print(json.dumps({'pid': pid}), flush=True)
    _, status = os.waitpid(pid, 0)
    print(json.dumps({'rc': os.waitstatus_to_exitcode(status)}), flush=True)
'''


class ForkedCli:
    """``run(*argv, cwd=...)``: ``pneumatic-servo argv`` in a fresh forked process, its
    result as ``subprocess.run(..., capture_output=True, text=True)`` gives it."""

    def __init__(self, env: dict):
        self.env = env
        self.server = self._start()
        # the outputs apart from the call's directory, which a case may make unwritable
        self.outputs = Path(tempfile.mkdtemp(prefix='forked_cli_'))

    def _start(self) -> subprocess.Popen:
        server = subprocess.Popen([sys.executable, '-c', SERVER], env=self.env, text=True,
                                  stdin=subprocess.PIPE, stdout=subprocess.PIPE)
        # its replies, read as PipeLines reads them: a fast call's two come at once
        self._lines = PipeLines(server.stdout)
        return server

    def _reply(self, timeout: float) -> dict:
        line = self._lines.next(timeout)
        if line is None:
            raise TimeoutError(f'no answer in {timeout:g} s')
        if not line:
            raise RuntimeError(f'the CLI server ended (exit {self.server.wait()})')
        return json.loads(line)

    def run(self, *argv, cwd, timeout: float = 300.0,
            settle: float = 0.0) -> subprocess.CompletedProcess:
        """``settle`` (s): wait this long before reading the replies, so that a fast call's
        two replies are both in the pipe when the first is read."""
        out, err = self.outputs / 'stdout', self.outputs / 'stderr'
        self.server.stdin.write(json.dumps({'argv': [str(a) for a in argv], 'cwd': str(cwd),
                                            'out': str(out), 'err': str(err)}) + '\n')
        self.server.stdin.flush()
        time.sleep(settle)
        pid = self._reply(30.0)['pid']
        try:
            rc = self._reply(timeout)['rc']
        except TimeoutError:
            raise TimeoutError(f'{argv} gave no answer in {timeout:g} s; its stacks:\n'
                               f'{self._stop(pid, err)}') from None
        result = subprocess.CompletedProcess(argv, rc, out.read_text(), err.read_text())
        out.unlink()
        err.unlink()
        return result

    def _stop(self, pid: int, err: Path) -> str:
        """Stop an overrunning call, and a server whose replies would now be out of step
        with the next call's (a new one is started): what the call wrote to stderr, with
        its stacks."""
        with contextlib.suppress(ProcessLookupError):
            os.kill(pid, signal.SIGUSR1)
            time.sleep(2.0)
            os.kill(pid, signal.SIGKILL)
        self.server.kill()
        self.server.wait()
        self.server = self._start()
        return err.read_text()[-6000:] if err.exists() else '(none)'

    def close(self) -> None:
        self.server.stdin.close()
        self.server.wait(30)
        for path in self.outputs.iterdir():
            path.unlink()
        self.outputs.rmdir()
