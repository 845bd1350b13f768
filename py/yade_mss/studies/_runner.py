"""One count of a triaxial study, run by YADE: ``yade -n -x _runner.py TASK.json`` (:func:`triaxialStudy` starts
it). Writes result.json beside the task when done, progress.json as it goes, error.json when it cannot go on;
SIGINT and SIGTERM save a checkpoint and end with status 130 / 143. Not imported by the package."""

import json
import os
import signal
import sys
import time

from yade_mss.base import atomicWrite
from yade_mss.studies._study import loadTemplates
from yade_mss.studies._triaxial import triaxial
from yade_mss.yade import MssTemplate


def _write(path, data):
    text = json.dumps(data)

    def write(tmp):
        with open(tmp, 'w') as f:
            f.write(text)
    atomicWrite(path, write, 'triaxial')


def main(taskPath):
    folder = os.path.dirname(os.path.abspath(taskPath))
    with open(taskPath) as f:
        task = json.load(f)
    started = time.time()
    last = [0.0]

    def progress(phase, fraction, text):
        if time.time() - last[0] >= 0.5:
            last[0] = time.time()
            _write(os.path.join(folder, 'progress.json'), dict(phase=phase, fraction=fraction, text=text,
                                                               elapsed=time.time() - started))

    def stop(signum, frame):  # once: the checkpoint is then written undisturbed
        signal.signal(signal.SIGINT, signal.SIG_IGN)
        signal.signal(signal.SIGTERM, signal.SIG_IGN)
        raise KeyboardInterrupt
    signal.signal(signal.SIGTERM, stop)
    signal.signal(signal.SIGINT, stop)
    templates = [MssTemplate(r) for r in loadTemplates(task, folder)]
    try:
        r = triaxial(templates, weights=[g['weight'] for g in task['templates']], checkpoint=folder,
                     progress=progress, n=task['n'], **task['options'])
    except KeyboardInterrupt:
        return 130
    except (ValueError, RuntimeError, TypeError) as e:
        _write(os.path.join(folder, 'error.json'), dict(n=task['n'], error=str(e)))
        print('triaxial n=%d: error: %s' % (task['n'], e), file=sys.stderr)
        return 1
    _write(os.path.join(folder, 'result.json'), dict(n=task['n'], digest=task['digest'], records=r.records,
                                                     compaction=r.compaction, cost=r.cost, derived=r.derived))
    return 0


if __name__ == '__main__' or 'yade' in sys.modules:
    code = main(sys.argv[1])
    sys.stdout.flush()
    os._exit(code)  # YADE's own exit would start its interactive shell's teardown; the status is ours
