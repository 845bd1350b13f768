"""``mss triaxial``: a triaxial test of grains' clumps in YADE at one or several sphere counts
(:func:`yade_mss.studies.triaxialStudy`); it starts YADE itself."""

import argparse
import sys

from ..base import exitStatus, stopOnce
from ..grains import optionTable
from ..studies import triaxialStudy, verdict


def main(argv=None):
    p = argparse.ArgumentParser(prog='mss triaxial', allow_abbrev=False,
                                description='a triaxial test of the grains\' clumps in YADE (periodic cell, '
                                'isotropic compaction, then drained or undrained shearing), at one or several '
                                'sphere counts: the same specimen at each (yade-mss)')
    p.add_argument('inputs', nargs='+', help='a grain (mesh or voxel volume; a labelled volume: each label a '
                   'grain), a folder of grains, a finished mss batch folder, or another generator\'s sphere file '
                   '(with --grain)')
    optionTable.addArguments(p, 'triaxial', skip=('nSpheres',))
    r = optionTable.row('nSpheres', 'triaxial')
    p.add_argument('--spheres', dest='counts', metavar='N,N,...', default=None,
                   help='%s [default %s]' % (r['help'], r['default']))
    a = p.parse_args(argv)
    seen = []
    stopOnce(seen=seen)  # SIGTERM as Ctrl-C: each count saves its checkpoint, the records are written
    try:
        v = optionTable.parsed('triaxial', a)
        try:  # each count as the table parses one
            if a.counts is not None:
                v['nSpheres'] = [optionTable.parseOne('nSpheres', 'triaxial', x) for x in a.counts.split(',')]
        except ValueError as e:
            raise ValueError(str(e).replace('options: nSpheres', '--spheres'))
        out = v.pop('output')
        scheduler = v.pop('scheduler', None)
        r = triaxialStudy(a.inputs, out, scheduler=scheduler, **v)
    except KeyboardInterrupt:
        print('\nmss triaxial: interrupted; what was recorded is written, each count saved where it was: run the '
              'same command again to resume', file=sys.stderr)
        return exitStatus(seen)
    except (ValueError, RuntimeError, TypeError, OSError) as e:
        print('mss triaxial: error: %s' % e, file=sys.stderr)
        return 1
    for row in sorted(r['summary'], key=lambda x: x['n']):
        print('n %-4d phi_peak %5.1f deg  phi_cs %5.1f deg  psi_max %5.1f deg  E50 %.3g Pa  e0 %.3f (clumps %.3f)  '
              'I_max %.2g%s  %d steps  %.1f s' % (row['n'], row['phi_peak_deg'], row['phi_cs_deg'], row['psi_max_deg'],
                                                 row['E50_Pa'], row['e0'], row['e0_union'], row['I_max'],
                                                 '' if row['quasi_static'] else ' NOT QUASI-STATIC', row['steps'],
                                                 row['wall_s']))
    if r['summary']:
        print(verdict(r['summary']))
    print('wrote %s: triaxial.csv, summary.csv, summary.json, report.html, the pictures' % r['outdir'])
    if r['failed']:
        for n, why in sorted(r['failed'].items()):
            print('mss triaxial: n=%d failed: %s' % (n, why), file=sys.stderr)
        return 1
    return 0
