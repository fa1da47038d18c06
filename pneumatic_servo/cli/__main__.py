"""``python -m pneumatic_servo.cli``: the same as the ``pneumatic-servo`` command."""
import sys

from . import main

sys.exit(main())
