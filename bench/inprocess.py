"""Generation inside a Python process (as a split during a simulation runs it): the femur from an in-memory mesh at
growing grids, 20 and 70 spheres, by default and on one thread; best of 5. The command line's figures are in
bench/speed.sh. Prints a table and appends a row a case to bench/results/inprocess.csv.
Run: PYTHONPATH=build/py /usr/bin/python3 bench/inprocess.py"""
import os
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from batch_scale import appendRows  # noqa: E402

import yade_mss  # noqa: E402
from yade_mss import _mss  # noqa: E402


def main():
    v, t = _mss.readMesh(os.path.join(HERE, '..', 'tests', 'data', 'human_femur.stl'))
    mesh = (np.reshape(v, (-1, 3)), np.reshape(t, (-1, 3)))
    rows = []
    print('OMP_WAIT_POLICY=%s' % os.environ.get('OMP_WAIT_POLICY'))
    print('%10s %8s %16s %7s %12s %12s' % ('resolution', 'spheres', 'grid', 'voxels', 'default ms', '1 thread ms'))
    for res in (20, 40, 60, 100):
        for n in (20, 70):
            best = {}
            for threads in (0, 1):
                ts = []
                for _ in range(5):
                    t0 = time.perf_counter()
                    r = yade_mss.generate(mesh, nSpheres=n, resolution=res, threads=threads)
                    ts.append(time.perf_counter() - t0)
                best[threads] = 1000 * min(ts)
            dims = r.grid['dims']
            rows.append([res, n, 'x'.join(map(str, dims)), int(np.prod(dims)), best[0], best[1]])
            print('%10d %8d %16s %7d %12.1f %12.1f' % tuple(rows[-1]))
    appendRows('inprocess.csv', ['resolution', 'spheres', 'grid', 'voxels', 'default_ms', 'one_thread_ms'], rows)


if __name__ == '__main__':
    main()
