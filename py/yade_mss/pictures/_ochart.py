"""The clump's simulation cost as a target (``mss ochart``, :func:`clumpOchart`): the three-dimensional analogue of
the spheropolygons' O-chart (seed paper 004, eq. 5-8, Fig. 4).

A DEM run costs about (spheres) / (time step), and the time step is proportional to the smallest radius (a
linear contact: sqrt(m / k) ~ r sqrt(rho / E)), so a clump's cost is T ~ n / r_min; we give it relative to one
sphere of the grain's volume (n = 1, r_min = r_eq: T = 1). Sweeping the sphere count n and the radius bound
r_min, scoring D on an independent grid, gives the error, the cost and O = T x D over the (n, r_min) plane, and
the Pareto front of (T, D): the clumps no other beats on both. Problem (iii) of the paper, the cheapest clump
meeting a fidelity D <= X, is the least T among the chart's points that meet it.
"""

import csv
import math
import os
import time

import numpy as np

from ..base import atomicWrite, checkSweep, integer as anInteger, number, progressBar
from ..grains import Mesh, compareMany, generate, optionTable, readGrain
from ._curve import counts as countList
from ._preview import pyplot, save

_COLUMNS = ['n_asked', 'rmin_fraction_asked', 'rmin_asked', 'n', 'r_min', 'r_min_voxels', 'D', 'T', 'O', 'pareto',
            'seconds', 'message']


def _range(name, value, integer):
    """(A, B) from 'A:B' (the command line's) or a pair, 0 < A <= B."""
    if isinstance(value, str):
        try:
            lo, hi = ((int if integer else float)(x) for x in value.split(':'))
        except ValueError:
            raise ValueError('ochart: %s takes A:B (two %s), got %r' % (name, 'integers' if integer else 'numbers',
                                                                       value))
    elif hasattr(value, '__len__') and len(value) == 2:
        lo, hi = ((anInteger('ochart', name, int(x) if isinstance(x, np.integer) else x) if integer
                   else number('ochart', name, x)) for x in value)
    else:
        raise TypeError('ochart: %s must be A:B or a pair, got %r' % (name, value))
    if not (0 < lo <= hi) or not math.isfinite(hi):
        raise ValueError('ochart: %s must satisfy 0 < A <= B, got %s:%s' % (name, lo, hi))
    return lo, hi


def pareto(points):
    """Indices of the points (T, D) no other point beats on both (at most as large in each, smaller in one)."""
    front = []
    for i, (t, d) in enumerate(points):
        beaten = any((t2 <= t and d2 <= d) and (t2 < t or d2 < d) for t2, d2 in points)
        if not beaten and (t, d) not in points[:i]:  # a clump found twice (a bound that did not bind) once
            front.append(i)
    return front


def cheapest(rows, dice):
    """The row of least cost T among those with D <= *dice* (ties: the lower D), or None."""
    ok = [r for r in rows if r['D'] != '' and r['D'] <= dice]
    return min(ok, key=lambda r: (r['T'], r['D'])) if ok else None


@optionTable.documented('ochart', skip=('counts', 'radii'))
def clumpOchart(grain, output, counts=None, radii='0.05:0.6', points=6, radiusPoints=5, dice=None,
                minCost=False, resolution=103, voxelSize=None, origin=None, label=None, maxProtrusion=None,
                scoreResolution=100, maxWork=None, scale=None):
    """The O-chart of a grain's clumps: for each sphere count n and radius bound rMin, the Dice mismatch D
    (eq. 27) on an independent grid (a mesh) or the volume's own voxels, the cost T = n / r_min relative to one
    sphere of the grain's volume, and O = T x D. Writes OUT.csv and the charts (OUT.png: D, T and O over the
    plane, and D against T with the Pareto front); with *minCost* also the clump chosen, OUT_best.csv.

    :param grain: a mesh file, voxel file, array or (vertices, triangles)
    :param output: the PNG to write
    :param counts: the sphere counts' range, 'A:B' or (A, B) (log-spaced, *points* of them; default 2:64)
    :param radii: the range of rMin as fractions of the grain's largest inscribed radius, 'A:B' or (A, B)
        (log-spaced, *radiusPoints* of them)
    :param int scoreResolution: the scoring grid of a mesh: voxels along the shortest edge (offset 0.37)
    OPTIONS
    :return: (rows, the row chosen or None); the chosen row's ``result`` is its :class:`MssResult`
    """
    lo, hi = _range('counts', '2:64' if counts is None else counts, True)
    if hi > 65535:
        raise ValueError('ochart: counts must be at most 65535, got %s' % hi)
    rlo, rhi = _range('radii', radii, False)
    points = optionTable.check('ochart', 'ochart', 'points', points)
    radiusPoints = optionTable.check('ochart', 'ochart', 'radiusPoints', radiusPoints)
    scoreResolution = anInteger('ochart', 'scoreResolution', scoreResolution, 1)  # as compare's --resolution
    if minCost and dice is None:
        raise ValueError('ochart: minCost needs dice, the fidelity to meet')
    if dice is not None:
        dice = optionTable.check('ochart', 'ochart', 'dice', dice)
    ns = countList(lo, hi, points)
    rs = sorted(set(float('%.4g' % x) for x in np.geomspace(rlo, rhi, radiusPoints)))
    if rhi > 1:
        raise ValueError('ochart: radii are fractions of the largest inscribed radius, at most 1, got %s:%s'
                         % (rlo, rhi))
    _refuseForeignTable(os.path.splitext(os.fspath(output))[0] + '.csv')
    s = readGrain(grain, voxelSize, origin, label, scale)
    mesh = isinstance(s, Mesh)
    kw = {'resolution': resolution} if mesh else {'voxelSize': s.voxelSize, 'origin': s.origin}
    score = {'resolution': scoreResolution} if mesh else {'voxelSize': s.voxelSize, 'origin': s.origin}
    src = (s.vertices, s.triangles) if mesh else np.frombuffer(s.data, dtype=np.uint8).reshape(s.shape, order='F')
    rows, results = [], {}
    volume = None
    # the grain's largest inscribed radius (on the generation grid), which the bounds are fractions of
    maxWork = optionTable.check('ochart', 'ochart', 'maxWork', optionTable.default('maxWork', 'ochart')
                             if maxWork is None else maxWork)
    t0 = time.perf_counter()
    inscribed = generate(src, nSpheres=1, maxProtrusion=maxProtrusion, maxWork=maxWork, **kw).metrics['inscribedRadius']
    # one generation of one sphere tells what the chart's will cost, each scored (as much again)
    rest = checkSweep('ochart', 2 * (time.perf_counter() - t0), 1, [n for n in ns for _ in rs], maxWork,
                            'ask for fewer points or radius points')
    bar = progressBar(len(ns) * len(rs), 'mss ochart', rest)
    for n in ns:
        for rv in rs:
            bar.update()
            t0 = time.perf_counter()
            row = dict({c: '' for c in _COLUMNS}, n_asked=n, rmin_fraction_asked=rv, rmin_asked=rv * inscribed)
            try:
                r = generate(src, nSpheres=n, rMin=rv * inscribed, maxProtrusion=maxProtrusion, maxWork=maxWork,
                             **kw)
            except ValueError as e:  # a bound the grain cannot hold: a point of the chart with no clump
                row.update(message=str(e), seconds=time.perf_counter() - t0)
                rows.append(row)
                continue
            volume = r.targetMass.volume
            c = compareMany(src, [r], maxWork=maxWork, **score)[0]
            h = r.grid['voxelSize']
            row.update(n=len(r), r_min=float(r.radii.min()), r_min_voxels=float(r.radii.min()) / h, D=c['dice'],
                       seconds=time.perf_counter() - t0)
            results[(n, rv)] = r
            rows.append(row)
    bar.close()
    if volume is None:
        raise ValueError('ochart: no point of the chart gave a clump (every radius bound exceeds the grain\'s '
                         'largest inscribed radius?)')
    req = (3 * volume / (4 * math.pi)) ** (1 / 3)  # one sphere of the grain's volume: T = 1
    done = [r for r in rows if r['D'] != '']
    for r in done:
        r['T'] = r['n'] * req / r['r_min']
        r['O'] = r['T'] * r['D']
    for i in pareto([(r['T'], r['D']) for r in done]):
        done[i]['pareto'] = 1
    for r in done:
        r['pareto'] = r['pareto'] or 0
    best = cheapest(done, dice) if minCost else None
    if best is not None:
        best['result'] = results[(best['n_asked'], best['rmin_fraction_asked'])]
    base = os.path.splitext(os.fspath(output))[0]

    def table(tmp):
        with open(tmp, 'w', newline='') as f:
            w = csv.DictWriter(f, fieldnames=_COLUMNS, extrasaction='ignore')
            w.writeheader()
            w.writerows(rows)
    atomicWrite(base + '.csv', table, 'ochart')
    if best is not None:
        best['result'].save(base + '_best.csv')
    _figure(rows, ns, rs, output, getattr(s, 'name', 'grain'), dice, best, mesh, scoreResolution)
    return rows, best


def _refuseForeignTable(path):
    """Before any work: OUT.csv, which the chart writes beside its PNG, is replaced only when it is an O-chart
    table already (a rerun); any other file there is the user's (the bug: ``-o s.png`` wrote over s.csv)."""
    if not os.path.lexists(path):
        return
    try:
        with open(path, 'rb') as f:
            first = f.read(4096).split(b'\n', 1)[0].strip()
    except OSError as e:
        raise ValueError('ochart: %s (its table, beside the PNG): %s' % (path, e))
    if first.decode('utf-8', 'replace') != ','.join(_COLUMNS):
        raise ValueError('ochart: %s exists and is not an O-chart table: the chart writes its table there; not '
                         'overwritten: name another -o, or move the file' % path)


def _figure(rows, ns, rs, path, name, dice, best, mesh, scoreResolution):
    plt = pyplot()
    N, R = np.meshgrid(np.array(ns, float), np.array(rs, float), indexing='ij')
    at = {(r['n_asked'], r['rmin_fraction_asked']): r for r in rows}
    grid = {k: np.array([[at[(n, rv)][k] if at[(n, rv)][k] != '' else np.nan for rv in rs] for n in ns])
            for k in ('D', 'T', 'O')}
    # two by two, 12 inches wide: legible at a page's width (in a row of four, the text shrank to 6 points there)
    fig, axs = plt.subplots(2, 2, figsize=(12, 9.5), dpi=110)
    axs = axs.ravel()
    o = np.where(np.isfinite(grid['O']), grid['O'], np.inf)
    g = np.unravel_index(np.argmin(o), o.shape)
    titles = (('D', 'Dice mismatch D (eq. 27)'), ('T', 'cost T = n / r_min (one sphere of the volume: 1)'),
              ('O', 'O = T x D'))
    for ax, (k, title) in zip(axs, titles):
        z = np.log10(grid[k])
        cs = ax.contourf(N, R, np.ma.masked_invalid(z), levels=14, cmap='viridis')
        ax.contour(N, R, np.ma.masked_invalid(z), levels=14, colors='k', linewidths=0.3)
        fig.colorbar(cs, ax=ax, label='log10 ' + k)
        ax.plot(N[g], R[g], 'r*', ms=16, mec='w', clip_on=False, zorder=5, label='least O')
        if best is not None:
            ax.plot(best['n_asked'], best['rmin_fraction_asked'], 'wo', ms=9, mec='k',
                    label='least T with D <= %.3g' % dice)
        missing = ~np.isfinite(grid[k])
        if missing.any():
            ax.plot(N[missing], R[missing], 'kx', ms=6, label='no clump (bound too large)')
        ax.set_xscale('log')
        ax.set_yscale('log')
        ax.set_xlabel('sphere count asked n')
        ax.set_ylabel('radius bound asked / largest inscribed radius')
        ax.set_title(title)
    axs[0].legend(fontsize=9, loc='upper right')
    done = [r for r in rows if r['D'] != '']
    front = sorted((r for r in done if r['pareto']), key=lambda r: r['T'])
    axs[3].loglog([r['T'] for r in done], [r['D'] for r in done], 'o', color='#999999', ms=5, label='chart points')
    axs[3].loglog([r['T'] for r in front], [r['D'] for r in front], 'o-', color='#c44e52', label='Pareto front')
    if dice is not None:
        axs[3].axhline(dice, color='k', lw=0.8, ls='--', label='D = %.3g' % dice)
    if best is not None:
        axs[3].loglog([best['T']], [best['D']], 'wo', ms=10, mec='k',
                      label='chosen: n %d, r_min %.3g voxels' % (best['n'], best['r_min_voxels']))
    axs[3].set_xlabel('cost T = n / r_min (relative)')
    axs[3].set_ylabel('D')
    axs[3].set_title('fidelity against cost')
    axs[3].grid(True, which='both', alpha=0.3)
    axs[3].legend(fontsize=9)
    fig.suptitle('%s: O-chart of the clumps (seed 004, Fig. 4, in 3-D)\nD %s; least O at n %d, bound %.3g'
                 % (name, 'on an independent grid of %d voxels, offset 0.37' % scoreResolution if mesh else
                    'on the volume\'s own voxels', N[g], R[g]))
    fig.tight_layout()
    save(fig, path, plt)
