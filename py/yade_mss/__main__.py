"""``python3 -m yade_mss COMMAND ...``: the commands of ``mss`` that run in Python (batch, preview, curve, ochart,
export, spheropolygon)."""
import sys

from ._batch import main as batch
from ._export import main as export
from ._ochart import main as ochart
from ._pictures import main as pictures
from ._spheropolygon import main as spheropolygon

if __name__ == '__main__':
    command = sys.argv[1] if len(sys.argv) > 1 else ''
    if command == 'batch':
        sys.exit(batch(sys.argv[2:]))
    if command == 'export':
        sys.exit(export(sys.argv[2:]))
    if command == 'ochart':
        sys.exit(ochart(sys.argv[2:]))
    if command == 'spheropolygon':
        sys.exit(spheropolygon(sys.argv[2:]))
    sys.exit(pictures(sys.argv[1:]))
