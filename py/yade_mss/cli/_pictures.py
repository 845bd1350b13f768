"""``mss preview`` and ``mss curve``: pictures of a clump against its grain, and of D against the sphere count."""

import argparse
import os
import sys

from ..base import refuseOverInputs
from ..grains import optionTable
from ..pictures import curve, preview


def main(argv=None):
    """``mss preview`` and ``mss curve``."""
    p = argparse.ArgumentParser(prog='mss', allow_abbrev=False,
                                description='pictures of clumps (yade-mss)')
    sub = p.add_subparsers(dest='command', required=True)
    pv = sub.add_parser('preview', allow_abbrev=False,
                        help='a clump against its grain: three views and a section, as PNG')
    pv.add_argument('grain')
    pv.add_argument('spheres')
    pv.add_argument('--title', default=None, help=argparse.SUPPRESS)  # mss generate --preview: the output's name
    optionTable.addArguments(pv, 'preview')
    cv = sub.add_parser('curve', allow_abbrev=False, help='D and time against the sphere count, as PNG and CSV')
    cv.add_argument('grain')
    optionTable.addArguments(cv, 'curve')
    cv.add_argument('--spheres', dest='oldSpheres', default=None, help=argparse.SUPPRESS)  # the name before --counts
    a = p.parse_args(argv)
    try:
        v = optionTable.parsed(a.command, a)
        grain = dict(voxelSize=v.get('voxelSize'), origin=v.get('origin'), label=v.get('label'), scale=v.get('scale'))
        if a.command == 'preview':
            refuseOverInputs('preview', [('-o', v['output'])], [a.grain, a.spheres])
        else:
            refuseOverInputs('curve', [('-o', v['output']), ('its CSV', os.path.splitext(v['output'])[0] + '.csv')],
                             [a.grain] + list(v.get('compare', [])))
        if a.command == 'preview':
            resolution = v.get('resolution', optionTable.default('resolution', 'preview'))
            row = preview(a.grain, a.spheres, v['output'], resolution,
                          title=a.title or os.path.basename(a.spheres), maxWork=v.get('maxWork'), **grain)
            print('wrote       %s  (n %d, D %.4f, largest protrusion %.4g)' % (v['output'], row['spheres'],
                                                                            row['dice'], row['protrusion']))
        else:
            counts = v.get('counts')
            if a.oldSpheres is not None:
                print('mss curve: warning: --spheres A:B is now --counts A:B', file=sys.stderr)
                counts = counts or a.oldSpheres
            if counts is None:
                raise ValueError('curve: --counts A:B is required')
            try:
                lo, hi = (int(x) for x in counts.split(':'))
            except ValueError:
                raise ValueError('curve: --counts takes A:B (two integers), got %r' % counts)
            points = v.get('points', optionTable.default('points', 'curve'))
            out = v['output']
            rows = curve(a.grain, lo, hi, out, points, v.get('compare', []),
                         v.get('resolution', optionTable.default('resolution', 'curve')),
                         maxProtrusion=v.get('maxProtrusion'), maxWork=v.get('maxWork'), **grain)
            print('wrote       %s and %s.csv  (%d counts, D %.4f at n %d to %.4f at n %d)'
                  % (out, os.path.splitext(out)[0], len(rows), rows[0]['D'], rows[0]['n'], rows[-1]['D'],
                     rows[-1]['n']))
    except (ValueError, RuntimeError) as e:
        print('mss %s: error: %s' % (a.command, e), file=sys.stderr)
        return 1
    return 0
