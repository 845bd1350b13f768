"""Scale of mss batch on a line-segmented specimen: a box cut into Voronoi cells whose touching faces are
separated by a line of background voxels, as a watershed segmentation draws them (no two grains share a face;
every contact lies across a line, found with the default contact gap of one voxel). For each count in
MSS_GRAINS (default 1000,10000,100000; about MSS_VOXELS voxels a grain, default 1000, MSS_SPHERES spheres,
default 8) the volume is written to disk and memory-mapped, then run as one process, --workers 2 and a local
Dask cluster (scheduler + 2 workers), each run a process of its own so that its peak memory is its own; then,
for the largest count, mssAssembly of the finished folder in YADE (time and peak memory). Prints grains per
second, the cost per grain against the smallest count's, the batch's overhead over its grains' generation
times, the peak memory (the batch process, and of it the anonymous memory: the rest is the mapped volume's
pages; its local workers), the contacts kept, and appends a row per run to bench/results/batch_scale.csv.
Run on a quiet machine: /usr/bin/python3 bench/batch_scale.py (MSS_RUNS='one process' to run one way only,
MSS_ASSEMBLY=0 to leave YADE out). It measures this checkout's build (build/py: rows.useBuild), never a
yade_mss installed elsewhere."""
import csv
import json
import os
import resource
import subprocess
import sys
import tempfile
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import rows as _rows  # noqa: E402 (bench/rows.py)

BUILD = _rows.useBuild()
COUNTS = [int(x) for x in os.environ.get('MSS_GRAINS', '1000,10000,100000').split(',')]
VOXELS = int(os.environ.get('MSS_VOXELS', '1000'))
SPHERES = int(os.environ.get('MSS_SPHERES', '8'))
RUNS = os.environ.get('MSS_RUNS', 'one process;workers 2;dask, 2 workers').split(';')


def specimen(path, cells, seed=7):
    """A box of about VOXELS voxels per cell, cut into Voronoi cells (labels 1..cells) separated by watershed
    lines (a voxel beside one of a higher label is cleared: yade_mss._specimen.separated), written as int32
    .npy a slab at a time: the volume is never whole in memory."""
    from scipy.spatial import cKDTree
    from yade_mss.grains import separated
    side = int(round((VOXELS * cells) ** (1 / 3)))
    rng = np.random.default_rng(seed)
    tree = cKDTree(rng.uniform(0, side, (cells, 3)))
    out = np.lib.format.open_memmap(path, mode='w+', dtype=np.int32, shape=(side, side, side))
    j, k = np.meshgrid(np.arange(side), np.arange(side), indexing='ij')

    def layer(i):
        pts = np.column_stack([np.full(j.size, i), j.ravel(), k.ravel()]).astype(float)
        return (tree.query(pts)[1] + 1).reshape(side, side).astype(np.int32)
    step = 32
    below, block = None, np.stack([layer(i) for i in range(min(step, side))])
    for i0 in range(0, side, step):
        nxt = np.stack([layer(i) for i in range(i0 + step, min(i0 + 2 * step, side))]) if i0 + step < side \
            else None
        parts = [p for p in (below, block, nxt[:1] if nxt is not None else None) if p is not None]
        cut = separated(np.concatenate(parts))  # with a layer of each neighbour: the lines across slabs too
        start = 1 if below is not None else 0
        out[i0:i0 + len(block)] = cut[start:start + len(block)]
        below, block = block[-1:], nxt
    out.flush()
    return side


def _anonPeak(peak):
    """Samples this process's anonymous memory (RssAnon: the heap; a mapped volume's pages are the page cache's,
    counted in RSS but given back under pressure) every 5 ms into peak[0], MiB."""
    while True:
        with open('/proc/self/status') as f:
            for line in f:
                if line.startswith('RssAnon:'):
                    peak[0] = max(peak[0], int(line.split()[1]) / 1024)
        time.sleep(0.005)


def child(path, label, scheduler):
    import threading
    from yade_mss import batch
    anon = [0.0]
    threading.Thread(target=_anonPeak, args=(anon,), daemon=True).start()
    t = time.perf_counter()
    b = batch([path], os.path.join(os.path.dirname(path), label.replace(' ', '_').replace(',', '')),
              nSpheres=SPHERES, progress=False, workers=1 if label == 'one process' else 2, scheduler=scheduler)
    wall = time.perf_counter() - t
    gen = sum(float(r['seconds']) for r in b.rows.values() if r['status'] == 'ok')
    print(json.dumps({'wall': wall, 'gen': gen, 'ok': sum(1 for r in b.rows.values() if r['status'] == 'ok'),
                      'kept': b.contacts['kept'], 'pairs': b.contacts['between'],
                      'self': resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024, 'anon': anon[0],
                      'children': resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024}))


ASSEMBLY = """
import json, resource, sys, time
from yade_mss import mssAssembly
O.materials.append(FrictMat(density=2650, young=1e8, label='grain'))
t = time.perf_counter()
a = mssAssembly(sys.argv[-1], material='grain')
wall = time.perf_counter() - t
print('MSSJSON ' + json.dumps({'wall': wall, 'clumps': len(a), 'bodies': len(O.bodies),
                               'peak': resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}))
"""


def assembly(outdir):
    """mssAssembly of a finished batch folder in real YADE (a process of its own): time and peak memory."""
    script = os.path.join(os.path.dirname(outdir), 'assembly.py')
    with open(script, 'w') as f:
        f.write(ASSEMBLY)
    p = subprocess.run(['yade', '-n', '-x', script, outdir], capture_output=True, text=True)
    line = next((l for l in p.stdout.splitlines() if l.startswith('MSSJSON ')), None)
    if line is None:
        raise SystemExit('mssAssembly failed:\n%s' % (p.stdout[-2000:] + p.stderr[-3000:]))
    return json.loads(line[8:])


def meta():
    """The row's date (UTC), commit (bench/rows.py: '+dirty' for changes under py/ or pkg/), machine and load."""
    return [time.strftime('%Y-%m-%dT%H:%M:%S', time.gmtime()), _rows.commit(), _rows.machine(),
            open('/proc/loadavg').read().split()[0]]


def appendRows(name, columns, rows, fmt='%.4g'):
    """Appends *rows* to bench/results/NAME, each after the run's date, commit, machine and load (meta()); the
    header (those four, then *columns*) when the file is new. Floats are written with *fmt* (None: as they are).
    :return: the file's path"""
    out = os.path.join(os.path.dirname(os.path.abspath(__file__)), 'results', name)
    new = not os.path.exists(out)
    m = meta()
    with open(out, 'a', newline='') as f:
        w = csv.writer(f)
        if new:
            w.writerow(['date', 'commit', 'machine', 'load'] + list(columns))
        for r in rows:
            w.writerow(m + [fmt % x if fmt and isinstance(x, float) else x for x in r])
    return out


def runs(path, d):
    """Each way of RUNS on the specimen at *path*, as it finishes: (label, the child's figures, its stderr)."""
    for label in RUNS:
        procs, address = [], None
        if label.startswith('dask'):
            sched = os.path.join(d, 'scheduler.json')
            procs = [subprocess.Popen(['dask-scheduler', '--host', '127.0.0.1', '--port', '0', '--no-dashboard',
                                       '--scheduler-file', sched], stdout=subprocess.DEVNULL,
                                      stderr=subprocess.DEVNULL)]
            while not os.path.exists(sched):
                time.sleep(0.1)
            time.sleep(0.5)
            procs += [subprocess.Popen(['dask-worker', '--scheduler-file', sched, '--nthreads', '1', '--no-dashboard'],
                                       stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL) for _ in range(2)]
            with open(sched) as f:
                address = json.load(f)['address']
            from distributed import Client
            with Client(address) as c:
                c.wait_for_workers(2, timeout=60)
        try:
            p = subprocess.run([sys.executable, __file__, '--child', path, label, address or ''],
                               capture_output=True, text=True)
        finally:
            for q in procs:
                q.kill()
            if label.startswith('dask'):
                os.remove(sched)
        if p.returncode != 0:
            raise SystemExit('%s failed:\n%s' % (label, p.stderr[-3000:]))
        yield label, json.loads(p.stdout.strip().splitlines()[-1]), p.stderr


def main():
    import yade_mss
    print('measuring %s (commit %s)' % (os.path.dirname(yade_mss.__file__), meta()[1]))
    print('%-8s %-17s %8s %10s %12s %9s %14s %14s %16s %14s' % (
        'grains', 'run', 'wall s', 'grains/s', 'ms a grain', 'vs first', 'peak MiB batch', 'of it anon.',
        'peak MiB workers', 'contacts kept'))
    first, rows = previousFirst(), []
    for n in COUNTS:
        d = tempfile.mkdtemp()
        path = os.path.join(d, 'spec.npy')
        t0 = time.perf_counter()
        side = specimen(path, n)
        print('specimen %d Voronoi cells with watershed lines in %d^3 voxels (%.0f MB of int32), made in %.0f s; '
              'load %s' % (n, side, side ** 3 * 4 / 2 ** 20, time.perf_counter() - t0,
                           open('/proc/loadavg').read().split()[0]), flush=True)
        for label, r, err in runs(path, d):
            workers = 1 if label == 'one process' else 2
            per = 1000 * r['wall'] / max(1, r['ok'])
            first.setdefault(label, per)
            over = 100 * (r['wall'] - r['gen'] / workers) / r['wall']
            print('%-8d %-17s %8.1f %10.1f %12.2f %8.2fx %14.0f %14.0f %16s %14s' % (
                n, label, r['wall'], r['ok'] / r['wall'], per, per / first[label], r['self'], r['anon'],
                '%.0f' % r['children'] if label == 'workers 2' else '-', '%d/%d' % (r['kept'], r['pairs'])),
                flush=True)
            rows.append([n, label, '%.2f' % r['wall'], '%.1f' % (r['ok'] / r['wall']), '%.0f' % over,
                         '%.0f' % r['self'], '%.0f' % r['children'] if label == 'workers 2' else '',
                         '%d/%d' % (r['kept'], r['pairs']), int('Large object' in err or 'Traceback' in err),
                         '%.0f' % r['anon'], '%.3f' % per, '%.2f' % (per / first[label]), 'lines',
                         SPHERES, VOXELS, '', '', ''])
            save(rows)  # after each run: a bench cut short keeps what it measured
            rows = []
        if n == COUNTS[-1] and os.environ.get('MSS_ASSEMBLY', '1') != '0':
            out = os.path.join(d, RUNS[0].replace(' ', '_').replace(',', ''))
            a = assembly(out)
            print('mssAssembly of %d grains in YADE: %.1f s, %d bodies, peak %.0f MiB'
                  % (a['clumps'], a['wall'], a['bodies'], a['peak']), flush=True)
            rows.append([n, 'mssAssembly in YADE', '%.2f' % a['wall'], '%.1f' % (a['clumps'] / a['wall']), '',
                         '', '', '', 0, '', '%.3f' % (1000 * a['wall'] / a['clumps']), '', 'lines', SPHERES, VOXELS,
                         a['clumps'], a['bodies'], '%.0f' % a['peak']])
            save(rows)
            rows = []
        subprocess.run(['rm', '-rf', d])


def previousFirst():
    """{run: ms a grain} of the newest rows of 1000 grains of the same specimen, spheres and grain size in
    bench/results/batch_scale.csv, when this run starts above 1000 grains (its cost is compared with theirs)."""
    out = {}
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), 'results', 'batch_scale.csv')
    if COUNTS[0] <= 1000 or not os.path.exists(path):
        return out
    with open(path, newline='') as f:
        for r in csv.DictReader(f):
            if (r.get('grains') == '1000' and r.get('specimen') == 'lines' and r.get('spheres') == str(SPHERES)
                    and r.get('voxels_per_grain') == str(VOXELS) and r.get('ms_per_grain')):
                out[r['run']] = float(r['ms_per_grain'])
    return out


def save(rows):
    """Appends *rows* (after the run's date, commit, machine and load) to bench/results/batch_scale.csv."""
    out = os.path.join(os.path.dirname(os.path.abspath(__file__)), 'results', 'batch_scale.csv')
    header = ['date', 'commit', 'machine', 'load', 'grains', 'run', 'wall_s', 'grains_per_s', 'overhead_pct',
              'peak_mib_batch', 'peak_mib_workers', 'contacts_kept', 'dask_noise', 'peak_anon_mib_batch',
              'ms_per_grain', 'cost_vs_first', 'specimen', 'spheres', 'voxels_per_grain', 'clumps', 'bodies',
              'peak_mib_yade']
    with open(out) if os.path.exists(out) else open(os.devnull) as f:
        old = list(csv.reader(f)) or [header]
    old = [header] + [r + [''] * (len(header) - len(r)) for r in old[1:]]  # rows from before a column was added
    m = meta()
    with open(out, 'w', newline='') as f:
        csv.writer(f).writerows(old + [m + r for r in rows])
    print('appended %s' % out)


if __name__ == '__main__':
    if sys.argv[1:2] == ['--child']:
        child(sys.argv[2], sys.argv[3], sys.argv[4] or None)
    else:
        main()
