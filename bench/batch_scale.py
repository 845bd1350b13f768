"""Scale of mss batch: a synthetic specimen of 500 grains, one process vs --workers 2 vs a local Dask cluster
(scheduler + 2 workers). Prints grains per second, the batch's overhead over the sum of its grains' generation
times, parallel efficiency and peak memory. Run: PYTHONPATH=build/py /usr/bin/python3 bench/batch_scale.py"""
import json
import os
import resource
import subprocess
import sys
import tempfile
import time

import numpy as np

from yade_mss import batch, regions, syntheticSpecimen

N = int(os.environ.get('MSS_GRAINS', '500'))
t0 = time.perf_counter()
L = syntheticSpecimen((360, 360, 360), N, size=(8, 16), seed=7)
rs = regions(L)
print('specimen     %d grains (%d cut by the border) in 360^3 voxels, made in %.1f s; load %s'
      % (len(rs), sum(r.touchesBorder for r in rs), time.perf_counter() - t0, open('/proc/loadavg').read().split()[0]))
d = tempfile.mkdtemp()
path = os.path.join(d, 'spec.npy')
np.save(path, L)
del L


def run(label, **kw):
    out = os.path.join(d, label.replace(' ', '_'))
    t = time.perf_counter()
    b = batch([path], out, nSpheres=30, progress=False, **kw)
    wall = time.perf_counter() - t
    gen = sum(float(r['seconds']) for r in b.rows.values() if r['status'] == 'ok')
    ok = sum(1 for r in b.rows.values() if r['status'] == 'ok')
    return label, wall, gen, ok, out


rows = [run('one process', workers=1), run('workers 2', workers=2)]
sched = os.path.join(d, 'scheduler.json')
procs = [subprocess.Popen(['dask-scheduler', '--host', '127.0.0.1', '--port', '0', '--no-dashboard',
                           '--scheduler-file', sched], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)]
while not os.path.exists(sched):
    time.sleep(0.1)
time.sleep(0.5)
procs += [subprocess.Popen(['dask-worker', '--scheduler-file', sched, '--nthreads', '1', '--no-dashboard'],
                           stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL) for _ in range(2)]
from distributed import Client  # noqa: E402
address = json.load(open(sched))['address']
with Client(address) as c:
    c.wait_for_workers(2, timeout=60)
try:
    rows.append(run('dask, 2 workers', scheduler=address))
finally:
    for p in procs:
        p.kill()
print('%-17s %8s %10s %12s %11s %9s' % ('run', 'wall s', 'grains/s', 'sum gen. s', 'efficiency', 'overhead'))
base = rows[0][1]
for label, wall, gen, ok, out in rows:
    workers = 1 if label == 'one process' else 2
    print('%-17s %8.2f %10.1f %12.2f %10.0f%% %8.0f%%' % (label, wall, ok / wall, gen, 100 * base / (workers * wall),
                                                        100 * (wall - gen / workers) / wall))
same = len(set(open(os.path.join(r[4], 'assembly.txt')).read() for r in rows)) == 1
print('same assembly from all three: %s' % same)
local2, dask2 = rows[1][1], rows[2][1]
print('efficiency: one-process time / (2 x wall); overhead: share of the wall time not spent generating '
      '(sum of grain times / workers); Dask vs --workers 2: %+.0f%%' % (100 * (dask2 / local2 - 1)))
print('peak memory: this process %.0f MiB, largest child %.0f MiB'
      % (resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
         resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024))
