"""D and generation time against the sphere count (``mss curve``, :func:`curve`): a chart and its CSV."""

import csv
import math
import os
import time

import numpy as np

from ..base import atomicWrite, checkSweep, progressBar
from ..grains import Mesh, compareMany, generate, optionTable, readGrain
from ._preview import pyplot, save


def counts(lo, hi, points=12):
    """About *points* sphere counts from *lo* to *hi*, evenly on a log scale, each once."""
    if not (1 <= lo <= hi):
        raise ValueError('curve: the sphere counts must satisfy 1 <= A <= B, got %s:%s' % (lo, hi))
    return sorted(set(int(round(x)) for x in np.geomspace(lo, hi, max(2, points))))


def curve(grain, lo, hi, path, points=12, compare=(), resolution=103, scoreResolution=100, voxelSize=None,
          origin=None, label=None, maxProtrusion=None, maxWork=None, scale=None):
    """D (independent grid) and generation time against the sphere count, as a chart (PNG) and a CSV beside it
    (``OUT.csv``: generator, n, D, eta, protrusion, seconds). Sphere files of other generators (*compare*) are
    added as labelled points (and rows named after their files). The grain is read once for the whole sweep.
    *maxProtrusion*: as :func:`generate` (default one voxel; ``inf``: unbounded).

    :return: the rows written (list of dicts)
    """
    plt = pyplot()
    s = readGrain(grain, voxelSize, origin, label, scale)
    kw = {'resolution': resolution} if isinstance(s, Mesh) else {'voxelSize': s.voxelSize, 'origin': s.origin}
    src = (s.vertices, s.triangles) if isinstance(s, Mesh) else np.frombuffer(
        s.data, dtype=np.uint8).reshape(s.shape, order='F')
    maxWork = optionTable.check('curve', 'curve', 'maxWork', optionTable.default('maxWork', 'curve')
                             if maxWork is None else maxWork)
    ns = counts(lo, hi, points)

    def step(n):
        """One point: (its row, the seconds it took, generation and scoring)."""
        t0 = time.perf_counter()
        r = generate(src, nSpheres=n, maxProtrusion=maxProtrusion, maxWork=maxWork, **kw)
        sec = time.perf_counter() - t0
        c = compareMany(src, [r], resolution=scoreResolution, maxWork=maxWork, **(
            {} if isinstance(s, Mesh) else {'voxelSize': s.voxelSize, 'origin': s.origin}))[0]
        return ({'generator': 'yade-mss', 'n': len(r), 'requested': n, 'D': c['dice'], 'eta': c['eta'],
                 'protrusion': c['protrusion'], 'seconds': sec}, time.perf_counter() - t0)
    # the cheapest count, the dearest and the one halfway between (the counts are spaced evenly in log) first:
    # they tell what the rest will cost (a step's cost is not a power of its count: the count a grain can hold
    # at a resolution caps it)
    first, firstSeconds = step(ns[0])
    done = {ns[0]: first}
    middle = min(ns, key=lambda n: abs(math.log(n) - 0.5 * math.log(ns[0] * ns[-1])))
    probes = sorted(set([ns[-1], middle]) - {ns[0]})
    measured = []
    for n in probes:
        done[n], seconds = step(n)
        measured.append((n, seconds))
    rest = [n for n in ns if n not in done]
    seconds = checkSweep('curve', firstSeconds, ns[0], rest, maxWork, 'ask for fewer points or a smaller range of '
                         'counts', measured)
    bar = progressBar(len(rest), 'mss curve', seconds)
    for n in rest:
        done[n] = step(n)[0]
        bar.update()
    bar.close()
    rows = [done[n] for n in ns]
    others = []
    for f in compare:
        c = compareMany(src, [f], resolution=scoreResolution, align='none', **(
            {} if isinstance(s, Mesh) else {'voxelSize': s.voxelSize, 'origin': s.origin}))[0]
        others.append({'generator': os.path.basename(os.fspath(f)), 'n': c['spheres'], 'requested': '',
                       'D': c['dice'], 'eta': c['eta'], 'protrusion': c['protrusion'], 'seconds': ''})
    base = os.path.splitext(os.fspath(path))[0]

    def table(tmp):
        with open(tmp, 'w', newline='') as f:
            w = csv.DictWriter(f, fieldnames=['generator', 'n', 'requested', 'D', 'eta', 'protrusion', 'seconds'])
            w.writeheader()
            w.writerows(rows + others)
    atomicWrite(base + '.csv', table, 'curve')  # exclusive, beside it (a fixed temporary name could be a link)
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(12, 4.8), dpi=100)
    ns = [r['n'] for r in rows]
    a1.loglog(ns, [r['D'] for r in rows], 'o-', label='yade-mss')
    for o in others:
        a1.loglog([o['n']], [o['D']], 's', label=o['generator'])
    a1.set_xlabel('number of spheres n')
    a1.set_ylabel('Dice mismatch D (eq. 27)')
    a1.set_title('fidelity')
    a1.grid(True, which='both', alpha=0.3)
    a1.legend(fontsize=8)
    a2.semilogx(ns, [r['seconds'] for r in rows], 'o-')
    a2.set_xlabel('number of spheres n')
    a2.set_ylabel('generation time (s)')
    a2.set_title('cost (load %s)' % open('/proc/loadavg').read().split()[0] if os.path.exists('/proc/loadavg')
                 else 'cost')
    a2.grid(True, which='both', alpha=0.3)
    fig.suptitle('%s: D on an independent grid (%d voxels along the shortest edge, offset 0.37); generation at '
                 '%s' % (getattr(s, 'name', 'grain'), scoreResolution,
                         'resolution %d' % resolution if isinstance(s, Mesh) else 'the volume\'s voxels'))
    fig.tight_layout()
    save(fig, path, plt)
    return rows
