"""Lines from a child's pipe (``pipes.PipeLines``), as the compile helper and the forked CLI
harness read them."""
import subprocess
import sys

from pneumatic_servo.pipes import PipeLines

#: two lines written at once, then a pause, then a last line without its newline
CHILD = ("import sys, time; sys.stdout.write('first\\nsecond\\n'); sys.stdout.flush(); "
         "time.sleep(3); sys.stdout.write('last'); sys.stdout.flush()")


def test_two_lines_that_came_together_are_both_read_at_once():
    """The second of two lines that arrived together is returned without waiting (a
    ``select`` after a buffered ``readline`` waited for the child's next write); then a
    timeout is ``None``, and the end of the pipe gives its last line, then ``''``."""
    child = subprocess.Popen([sys.executable, '-c', CHILD], stdout=subprocess.PIPE, text=True)
    lines = PipeLines(child.stdout)
    assert lines.next(60.0) == 'first'
    # held, not awaited: the child sleeps 3 s now, so a wait for its next write would give
    # None at the 2 s timeout
    assert lines.next(2.0) == 'second'
    assert lines.next(0.0) is None
    assert lines.next(60.0) == 'last'
    assert lines.next(60.0) == ''
    child.wait()
