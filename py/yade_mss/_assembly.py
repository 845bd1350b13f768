"""Specimens in YADE: every grain of a labelled volume, or of a finished ``mss batch`` directory, as a clump at
its true position with its exact mass properties (:func:`mssAssembly`)."""

import json
import os

import numpy as np

from ._batch import GENERATE_OPTIONS, batch
from ._clumps import bodyOptions, buildClump
from ._keywords import split
from ._results import MssResult


def _finished(outdir):
    """{label or file: MssResult} of the grains an ``mss batch`` run wrote to *outdir* (status ok)."""
    g = os.path.join(outdir, 'grains')
    if not os.path.isdir(g):
        raise ValueError('mssAssembly: %s is not an mss batch output (no grains/ folder)' % outdir)
    out = {}
    for name in sorted(os.listdir(g)):
        if not name.endswith('.json'):
            continue
        with open(os.path.join(g, name)) as f:
            row = json.load(f)['row']
        if row['status'] == 'ok':
            key = row['label'] if row['label'] != '' else row['file']
            out[key] = MssResult.load(os.path.join(g, name[:-5] + '.npz'))
    return out


def mssAssembly(source, minVoxels=0, excludeBorder=False, labels=None, voxelSize=None, origin=None, **options):
    """Builds every grain of a specimen as a YADE clump at its true position, each with the grain's exact mass,
    centre of mass and inertia (as :func:`mssClump` with ``mass='target'``).

    :param source: a labelled volume (.npy or .tif file, or an integer array; 0 is background), or the output
        directory of a finished ``mss batch`` run (then nothing is generated)
    :param float voxelSize: the volume's voxel edge, world units (default 1)
    :param origin: the world position of the centre of its voxel (0, 0, 0), 3 numbers
    :param int minVoxels: skip grains of fewer voxels (as ``mss batch --min-voxels``)
    :param bool excludeBorder: skip grains cut by the volume's border
    :param labels: only these labels, a list of integers
    :param options: :func:`generate` keywords (nSpheres, dice, ...) and ``utils.sphere`` ones (material, color,
        mask, ...); unknown ones raise TypeError naming the closest
    :return: {label (or file name): (clumpId, [memberIds])}, in label order

    A volume is generated here, one grain after the other; for a large specimen run ``mss batch`` (processes
    side by side or a Dask cluster, resumable) and build from its directory.
    """
    gen, body = split('mssAssembly', options, [o for o in GENERATE_OPTIONS if o not in ('voxelSize', 'origin',
                                                                                        'label', 'threads')],
                      bodyOptions(),
                      extra=('source', 'minVoxels', 'excludeBorder', 'labels', 'voxelSize', 'origin'))
    if isinstance(source, (str, os.PathLike)) and os.path.isdir(source):
        if gen:
            raise ValueError('mssAssembly: %s: generation options do nothing for a finished batch'
                             % ', '.join(sorted(gen)))
        results = _finished(os.fspath(source))
    else:
        b = batch(source if isinstance(source, np.ndarray) else [source], None, workers=1,
                  minVoxels=minVoxels, excludeBorder=excludeBorder, labels=labels, voxelSize=voxelSize,
                  origin=origin, progress=False, **gen)
        if b.failed:
            raise RuntimeError('mssAssembly: grains failed: %s' % '; '.join(
                '%s: %s' % (k, b.rows[k]['message']) for k in b.failed[:5]))
        results = {b.rows[k]['label']: r for k, r in b.results.items()}
    from ._clumps import _yade
    utils, O, me = _yade()
    out = {}
    try:
        for key, r in results.items():
            m = r.targetMass
            out[key] = buildClump(r.centers, r.radii, m.volume, m.centroid, m.inertia, body)
    except Exception:
        for cid, ids in out.values():
            O.bodies.erase(cid, True)
        raise
    return out
