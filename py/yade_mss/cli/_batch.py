"""``mss batch``: a CT specimen or a folder of grains to a DEM assembly (:func:`yade_mss.batch`)."""

import argparse
import sys

from ..base import exitStatus, stopOnce
from ..grains import optionTable
from ..specimens import batch, clusterSecurity


def main(argv=None):
    p = argparse.ArgumentParser(prog='mss batch', allow_abbrev=False,
                                description='a CT specimen or a folder of grains to a DEM '
                                'assembly (yade-mss)')
    p.add_argument('inputs', nargs='+', help='a labelled volume (.npy, .tif; 0 is background), or mesh/volume '
                   'files, or directories of them')
    optionTable.addArguments(p, 'batch')
    a = p.parse_args(argv)
    seen = []
    stopOnce(seen=seen)  # SIGTERM (a `kill` of the batch) as Ctrl-C: the workers end, what is finished is kept
    try:
        v = optionTable.parsed('batch', a)
        own = ('output', 'workers', 'scheduler', 'tlsCaFile', 'tlsCert', 'tlsKey', 'minVoxels', 'excludeBorder',
               'labels', 'previews', 'voxelSize', 'origin', 'density', 'young', 'format', 'segment', 'segmentH',
               'segmentMarkers',
               'connectTimeout')
        gen = {k: x for k, x in v.items() if k not in own}
        labels = [int(x) for x in v['labels'].split(',')] if v.get('labels') else None
        b = batch(a.inputs, v['output'], workers=v.get('workers'), scheduler=v.get('scheduler'),
                  minVoxels=v.get('minVoxels', 0),
                  security=clusterSecurity(None, v.get('tlsCaFile'), v.get('tlsCert'), v.get('tlsKey')),
                  excludeBorder=v.get('excludeBorder', False), labels=labels, voxelSize=v.get('voxelSize'),
                  origin=v.get('origin'), previews=v.get('previews', False), density=v.get('density', 1000.0),
                  young=v.get('young', 1e9), format=v.get('format'), segment=v.get('segment', False),
                  segmentH=v.get('segmentH'), segmentMarkers=v.get('segmentMarkers'),
                  connectTimeout=v.get('connectTimeout', 5.0), **gen)
    except KeyboardInterrupt:
        print('mss batch: interrupted; what was done is kept: run the same command again to continue',
              file=sys.stderr)
        return exitStatus(seen)
    except (ValueError, RuntimeError, OSError) as e:
        print('mss batch: error: %s' % e, file=sys.stderr)
        return 1
    if b.failed:
        print('mss batch: %d grains failed (see grains.csv)' % len(b.failed), file=sys.stderr)
        return 1
    return 0
