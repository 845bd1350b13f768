#!/usr/bin/python3
"""How generation cost grows: wall time (STL read to spheres written, median of REPEAT runs)
and peak memory of `mss generate` on the femur against the grid size (resolution 50, 100, 205, 400 voxels along
the shortest edge, 70 spheres) and against the sphere count (10 to 1000 at resolution 100), with the exponent of
a least-squares power law fitted to each (time ~ voxels^a, time ~ n^b).

usage: [REPEAT=3] bench/cost_growth.py [--quick]   (build first; MSS_BINARY overrides ./build/mss)
--quick: resolutions 50-205 and counts 10-300 only.
"""
import math
import os
import statistics
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
MSS = os.environ.get('MSS_BINARY', os.path.join(ROOT, 'build', 'mss'))
FEMUR = os.path.join(ROOT, 'tests', 'data', 'human_femur.stl')
REPEAT = int(os.environ.get('REPEAT', '3'))


def once(tmp, resolution, n):
    """(wall seconds as mss reports them, peak resident KiB, grid voxels, dice)"""
    mem = os.path.join(tmp, 'mem')
    out = subprocess.run(['/usr/bin/time', '-f', '%M', '-o', mem, MSS, 'generate', FEMUR, '--spheres', str(n),
                          '--resolution', str(resolution), '-o', os.path.join(tmp, 's.csv')],
                         check=True, capture_output=True, text=True).stdout
    fields = {line.split()[0]: line.split() for line in out.splitlines() if line.strip()}
    g = fields['grid']
    voxels = int(g[1]) * int(g[3]) * int(g[5])
    return float(fields['seconds'][-1]), int(open(mem).read().split()[-1]), voxels, float(fields['dice'][1])


def measure(tmp, resolution, n):
    runs = [once(tmp, resolution, n) for _ in range(REPEAT)]
    return statistics.median(r[0] for r in runs), max(r[1] for r in runs), runs[0][2], runs[0][3]


def slope(xs, ys):
    lx, ly = [math.log(x) for x in xs], [math.log(y) for y in ys]
    mx, my = statistics.mean(lx), statistics.mean(ly)
    return sum((a - mx) * (b - my) for a, b in zip(lx, ly)) / sum((a - mx) ** 2 for a in lx)


def main():
    quick = '--quick' in sys.argv
    print('load before: %s' % open('/proc/loadavg').read().strip())
    with tempfile.TemporaryDirectory() as tmp:
        print('\ngrid size (femur, 70 spheres; median of %d)' % REPEAT)
        print('%10s %12s %9s %10s %9s %8s' % ('resolution', 'voxels', 'seconds', 'peak MiB', 'B/voxel', 'D_gen'))
        rows = []
        for res in ((50, 100, 205) if quick else (50, 100, 205, 400)):
            t, kib, vox, d = measure(tmp, res, 70)
            rows.append((vox, t))
            print('%10d %12d %9.3f %10.1f %9.1f %8.4f' % (res, vox, t, kib / 1024, kib * 1024 / vox, d))
        print('time ~ voxels^%.2f' % slope(*zip(*rows)))
        print('\nsphere count (femur, resolution 100; median of %d)' % REPEAT)
        print('%10s %9s %10s %8s' % ('n', 'seconds', 'peak MiB', 'D_gen'))
        rows = []
        for n in ((10, 30, 100, 300) if quick else (10, 30, 100, 300, 1000)):
            t, kib, vox, d = measure(tmp, 100, n)
            rows.append((n, t))
            print('%10d %9.3f %10.1f %8.4f' % (n, t, kib / 1024, d))
        print('time ~ n^%.2f' % slope(*zip(*rows)))
    print('\nload after: %s' % open('/proc/loadavg').read().strip())


if __name__ == '__main__':
    main()
