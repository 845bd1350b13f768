"""``python3 -m yade_mss COMMAND ...``: see :mod:`yade_mss.cli`."""

import sys

from .cli import main

if __name__ == '__main__':
    sys.exit(main())
