"""Scale of mss batch: a dense specimen of MSS_GRAINS grains (default 10000: a box cut into Voronoi cells, every
grain touching its neighbours, so that the contacts are found and kept too), run as one process, --workers 2
and a local Dask cluster (scheduler + 2 workers). Each run is a process of its own, so that its peak memory is
its own. Prints grains per second, the batch's overhead over the sum of its grains' generation times, the
peak memory (the batch process, and of it the anonymous memory: the rest is the mapped volume's pages; its local
workers), and appends a row per run to bench/results/batch_scale.csv.
Run on a quiet machine: PYTHONPATH=build/py /usr/bin/python3 bench/batch_scale.py"""
import csv
import json
import os
import resource
import subprocess
import sys
import tempfile
import time

import numpy as np

N = int(os.environ.get('MSS_GRAINS', '10000'))
SPHERES = 20


def specimen(path, cells, seed=7):
    """A box of about 8000 voxels per cell, cut into Voronoi cells (labels 1..cells), written as int32 .npy."""
    from scipy.spatial import cKDTree
    side = int(round((8000 * cells) ** (1 / 3)))
    rng = np.random.default_rng(seed)
    tree = cKDTree(rng.uniform(0, side, (cells, 3)))
    out = np.lib.format.open_memmap(path, mode='w+', dtype=np.int32, shape=(side, side, side))
    j, k = np.meshgrid(np.arange(side), np.arange(side), indexing='ij')
    for i in range(side):  # a slab at a time: the volume never whole in memory
        pts = np.column_stack([np.full(j.size, i), j.ravel(), k.ravel()]).astype(float)
        out[i] = (tree.query(pts)[1] + 1).reshape(side, side)
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
    b = batch([path], os.path.join(os.path.dirname(path), label.replace(' ', '_')), nSpheres=SPHERES,
              progress=False, workers=1 if label == 'one process' else 2, scheduler=scheduler)
    wall = time.perf_counter() - t
    gen = sum(float(r['seconds']) for r in b.rows.values() if r['status'] == 'ok')
    print(json.dumps({'wall': wall, 'gen': gen, 'ok': sum(1 for r in b.rows.values() if r['status'] == 'ok'),
                      'kept': b.contacts['kept'], 'pairs': b.contacts['pairs'],
                      'self': resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024, 'anon': anon[0],
                      'children': resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024}))


def meta():
    commit = subprocess.run(['git', 'rev-parse', '--short', 'HEAD'], capture_output=True, text=True).stdout.strip()
    model = next((l.split(':', 1)[1].strip() for l in open('/proc/cpuinfo') if l.startswith('model name')), '?')
    return [time.strftime('%Y-%m-%dT%H:%M:%S', time.gmtime()), commit or 'unknown', '%d cores %s'
            % (os.cpu_count(), model), open('/proc/loadavg').read().split()[0]]


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


def main():
    d = tempfile.mkdtemp()
    path = os.path.join(d, 'spec.npy')
    t0 = time.perf_counter()
    side = specimen(path, N)
    print('specimen     %d Voronoi cells in %d^3 voxels (%.0f MB of int32), made in %.0f s; load %s'
          % (N, side, side ** 3 * 4 / 2 ** 20, time.perf_counter() - t0, open('/proc/loadavg').read().split()[0]))
    runs = []
    for label in ('one process', 'workers 2', 'dask, 2 workers'):
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
            address = json.load(open(sched))['address']
            from distributed import Client
            with Client(address) as c:
                c.wait_for_workers(2, timeout=60)
        try:
            p = subprocess.run([sys.executable, __file__, '--child', path, label, address or ''],
                               capture_output=True, text=True)
        finally:
            for q in procs:
                q.kill()
        if p.returncode != 0:
            raise SystemExit('%s failed:\n%s' % (label, p.stderr[-3000:]))
        runs.append((label, json.loads(p.stdout.strip().splitlines()[-1]), p.stderr))
    print('%-17s %8s %10s %12s %9s %14s %14s %16s' % ('run', 'wall s', 'grains/s', 'sum gen. s', 'overhead',
                                                     'peak MiB batch', 'of it anon.', 'peak MiB workers'))
    rows = []
    for label, r, err in runs:
        workers = 1 if label == 'one process' else 2
        over = 100 * (r['wall'] - r['gen'] / workers) / r['wall']
        print('%-17s %8.1f %10.1f %12.1f %8.0f%% %14.0f %14.0f %16s' % (
            label, r['wall'], r['ok'] / r['wall'], r['gen'], over, r['self'], r['anon'],
            '%.0f' % r['children'] if label == 'workers 2' else '-'))
        rows.append(meta() + [N, label, '%.2f' % r['wall'], '%.1f' % (r['ok'] / r['wall']), '%.0f' % over,
                              '%.0f' % r['self'], '%.0f' % r['children'] if label == 'workers 2' else '',
                              '%d/%d' % (r['kept'], r['pairs']), int('Large object' in err or 'Traceback' in err),
                              '%.0f' % r['anon']])
    print('contacts kept: %s; Dask warnings or tracebacks: %s' % (rows[0][11], 'yes' if any(r[12] for r in rows)
                                                                   else 'none'))
    out = os.path.join(os.path.dirname(os.path.abspath(__file__)), 'results', 'batch_scale.csv')
    header = ['date', 'commit', 'machine', 'load', 'grains', 'run', 'wall_s', 'grains_per_s', 'overhead_pct',
              'peak_mib_batch', 'peak_mib_workers', 'contacts_kept', 'dask_noise', 'peak_anon_mib_batch']
    old = list(csv.reader(open(out))) if os.path.exists(out) else [header]
    old = [header] + [r + [''] * (len(header) - len(r)) for r in old[1:]]  # rows from before a column was added
    with open(out, 'w', newline='') as f:
        csv.writer(f).writerows(old + rows)
    print('appended    %s' % out)


if __name__ == '__main__':
    if sys.argv[1:2] == ['--child']:
        child(sys.argv[2], sys.argv[3], sys.argv[4] or None)
    else:
        main()
