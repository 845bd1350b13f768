"""``python3 -m yade_mss COMMAND ...``: the commands of ``mss`` that run in Python (batch, preview, curve)."""
import sys

from ._batch import main as batch
from ._pictures import main as pictures

if __name__ == '__main__':
    command = sys.argv[1] if len(sys.argv) > 1 else ''
    sys.exit(batch(sys.argv[2:]) if command == 'batch' else pictures(sys.argv[1:]))
