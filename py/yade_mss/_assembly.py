"""Specimens in YADE: every grain of a labelled volume, or of a finished ``mss batch`` directory, as a clump at
its true position with its exact mass properties (:func:`mssAssembly`)."""

import csv
import json
import os

import numpy as np

from ._batch import GENERATE_OPTIONS, batch
from ._clumps import bodyOptions, buildClump
from ._keywords import split
from ._results import MssResult


class Assembly(dict):
    """What :func:`mssAssembly` built: {label (or file name): (clumpId, [memberIds])}, in label order, and
    what the specimen says of it.

    :ivar scanContacts: the pairs of keys whose grains touch in the scan (a labelled volume; else empty)
    """

    def __init__(self, items, scanContacts=()):
        dict.__init__(self, items)
        self.scanContacts = list(scanContacts)

    def timeStep(self):
        """The critical time step of the clumps' members as YADE's ``PWaveTimeStep`` computes it (each sphere's
        radius times sqrt(density / young) of its material), and the keys of the grains within 10% of it:
        (step, [keys])."""
        from ._clumps import _yade
        utils, O, me = _yade()
        steps = {}
        for key, (cid, ids) in self.items():
            for i in ids:
                b = O.bodies[i]
                dt = b.shape.radius * (b.material.density / b.material.young) ** 0.5
                steps[key] = min(steps.get(key, dt), dt)
        if not steps:
            return None, []
        least = min(steps.values())
        return least, sorted((k for k, t in steps.items() if t <= 1.1 * least), key=steps.get)

    def touching(self):
        """The pairs of keys whose clumps interact in YADE now (a real interaction between members of both;
        after a step, once the collider has run)."""
        from ._clumps import _yade
        utils, O, me = _yade()
        owner = {i: key for key, (cid, ids) in self.items() for i in ids}
        out = set()
        for i in O.interactions:
            if not i.isReal:
                continue
            a, b = owner.get(i.id1), owner.get(i.id2)
            if a is not None and b is not None and a != b:
                out.add((a, b) if str(a) < str(b) else (b, a))
        return out

    def contactsKept(self):
        """(how many of the scan's contacts between built grains interact in YADE now, how many there are)."""
        built = [(a, b) for a, b in self.scanContacts if a in self and b in self]
        now = self.touching()
        return sum(1 for a, b in built if ((a, b) if str(a) < str(b) else (b, a)) in now), len(built)


def _scanPairs(contacts):
    return [(int(c['a']), int(c['b'])) for c in contacts]


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
    :return: :class:`Assembly`: {label (or file name): (clumpId, [memberIds])}, in label order, with the scan's
        contacts (``contactsKept()`` after a step: how many interact in YADE) and ``timeStep()``

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
        contacts = []
        path = os.path.join(os.fspath(source), 'contacts.csv')
        if os.path.exists(path):
            with open(path, newline='') as f:
                contacts = list(csv.DictReader(f))
    else:
        b = batch(source if isinstance(source, np.ndarray) else [source], None, workers=1,
                  minVoxels=minVoxels, excludeBorder=excludeBorder, labels=labels, voxelSize=voxelSize,
                  origin=origin, progress=False, **gen)
        if b.failed:
            raise RuntimeError('mssAssembly: grains failed: %s' % '; '.join(
                '%s: %s' % (k, b.rows[k]['message']) for k in b.failed[:5]))
        results = {b.rows[k]['label']: r for k, r in b.results.items()}
        contacts = b.scanContacts or []
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
    return Assembly(out, _scanPairs(contacts))
