"""``mss ochart``: D, the simulation cost and O over sphere counts and radius bounds (:func:`yade_mss.clumpOchart`)."""

import argparse
import os
import sys

from ..base import refuseOverInputs
from ..grains import optionTable
from ..pictures import clumpOchart


def main(argv=None):
    p = argparse.ArgumentParser(prog='mss ochart', allow_abbrev=False,
                                description='D, the simulation cost n / r_min and O = cost x D '
                                'over sphere counts and radius bounds (yade-mss)')
    p.add_argument('grain')
    optionTable.addArguments(p, 'ochart')
    a = p.parse_args(argv)
    try:
        v = optionTable.parsed('ochart', a)
        if v.get('dice') is not None and not v.get('minCost'):
            raise ValueError('ochart: --dice X chooses the cheapest clump with D <= X and applies with --min-cost; '
                             'give --min-cost too, or leave --dice out')
        base = os.path.splitext(v['output'])[0]
        refuseOverInputs('ochart', [('-o', v['output']), ('its CSV', base + '.csv'),
                                    ('its best clump', base + '_best.csv')], [a.grain])
        rows, best = clumpOchart(a.grain, v['output'], v.get('counts'), v.get('radii', '0.05:0.6'), v.get('points', 6),
                                 v.get('radiusPoints', 5), v.get('dice'), v.get('minCost', False),
                                 v.get('resolution', optionTable.default('resolution', 'ochart')), v.get('voxelSize'),
                                 v.get('origin'), v.get('label'), v.get('maxProtrusion'), maxWork=v.get('maxWork'),
                                 scale=v.get('scale'))
    except (ValueError, RuntimeError) as e:
        print('mss ochart: error: %s' % e, file=sys.stderr)
        return 1
    base = os.path.splitext(v['output'])[0]
    done = [r for r in rows if r['D'] != '']
    print('wrote       %s and %s.csv  (%d points, %d with a clump, %d on the Pareto front)'
          % (v['output'], base, len(rows), len(done), sum(r['pareto'] for r in done)))
    if v.get('minCost'):
        if best is None:
            print('mss ochart: no point of the chart meets D <= %g: widen --counts or lower --radii' % v['dice'],
                  file=sys.stderr)
            return 1
        print('least cost  n %d, r_min %.4g (%.3g voxels), D %.4f, T %.4g  (the point n %d, rMin %.3g of the '
              'largest inscribed radius); wrote %s' % (best['n'], best['r_min'], best['r_min_voxels'], best['D'],
                                                       best['T'], best['n_asked'], best['rmin_fraction_asked'],
                                                       base + '_best.csv'))
    return 0
