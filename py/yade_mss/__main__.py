"""``python3 -m yade_mss COMMAND ...``: the commands of ``mss`` that run in Python (batch, preview, curve, ochart,
export, spheropolygon)."""
import sys

from ._batch import main as batch
from ._export import main as export
from ._ochart import main as ochart
from ._pictures import main as pictures
from ._spheropolygon import main as spheropolygon


def run(argv):
    command = argv[0] if argv else ''
    if command == 'batch':
        return batch(argv[1:])
    if command == 'export':
        return export(argv[1:])
    if command == 'ochart':
        return ochart(argv[1:])
    if command == 'spheropolygon':
        return spheropolygon(argv[1:])
    return pictures(argv)


if __name__ == '__main__':
    try:
        sys.exit(run(sys.argv[1:]))
    except KeyboardInterrupt:  # Ctrl-C: whatever was being written is not published (atomic writes)
        print('\nmss %s: interrupted (Ctrl-C)' % (sys.argv[1] if len(sys.argv) > 1 else ''), file=sys.stderr)
        sys.exit(130)
