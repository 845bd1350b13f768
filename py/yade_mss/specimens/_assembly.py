"""Specimens in YADE: every grain of a labelled volume, or of a finished ``mss batch`` directory, as a clump at
its true position with its exact mass properties (:func:`mssAssembly`)."""

import csv
import json
import os

import numpy as np

from ..base import split
from ..grains import GENERATE_OPTIONS
from ..yade import SCAN_BOX_TAG, bodyOptions, buildClump, requireVoxelSize, yadeModules
from . import _manifest
from ._batch import batch, grainRecord


class Assembly(dict):
    """What :func:`mssAssembly` built: {label (or file name): (clumpId, [memberIds])}, in label order, and
    what the specimen says of it.

    :ivar scanContacts: the pairs of keys whose grains touch in the scan (a labelled volume; else empty)
    """

    def __init__(self, items, scanContacts=(), contactGap=0.0):
        dict.__init__(self, items)
        self.scanContacts = list(scanContacts)
        self.contactGap = contactGap  # world units: the scan's tolerance (the contact gap times the voxel edge)

    def pairsWithin(self, gap=None):
        """The pairs of keys whose clumps' spheres come within *gap* (world units; default :attr:`contactGap`,
        the tolerance the scan's contacts were counted with) of each other in YADE now: the assembly's contacts,
        counted as the scan's were, whether YADE has an interaction there yet or not."""
        from scipy.spatial import cKDTree
        utils, O, me = yadeModules()
        gap = self.contactGap if gap is None else float(gap)
        keys, pos, rad, owner = list(self), [], [], []
        for n, key in enumerate(keys):
            for i in self[key][1]:
                b = O.bodies[i]
                pos.append([b.state.pos[0], b.state.pos[1], b.state.pos[2]])
                rad.append(b.shape.radius)
                owner.append(n)
        if len(set(owner)) < 2:
            return set()
        pos, rad, owner = np.array(pos), np.array(rad), np.array(owner)
        pairs = np.array(sorted(cKDTree(pos).query_pairs(2 * rad.max() + gap)), dtype=int).reshape(-1, 2)
        i, j = pairs[:, 0], pairs[:, 1]
        near = (owner[i] != owner[j]) & (np.linalg.norm(pos[i] - pos[j], axis=1) - rad[i] - rad[j] <= gap)
        out = set()
        for a, b in zip(owner[i[near]], owner[j[near]]):
            out.add(_ordered(keys[a], keys[b]))
        return out

    def timeStep(self):
        """The critical time step of the clumps' members as YADE's ``PWaveTimeStep`` computes it (each sphere's
        radius times sqrt(density / young) of its material), and the keys of the grains within 10% of it:
        (step, [keys])."""
        utils, O, me = yadeModules()
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
        utils, O, me = yadeModules()
        owner = {i: key for key, (cid, ids) in self.items() for i in ids}
        out = set()
        for i in O.interactions:
            if not i.isReal:
                continue
            a, b = owner.get(i.id1), owner.get(i.id2)
            if a is not None and b is not None and a != b:
                out.add(_ordered(a, b))
        return out

    def contactsKept(self):
        """(how many of the scan's contacts between built grains interact in YADE now, how many there are)."""
        built = [(a, b) for a, b in self.scanContacts if a in self and b in self]
        now = self.touching()
        return sum(1 for a, b in built if _ordered(a, b) in now), len(built)


def _ordered(a, b):
    """A pair of keys in order: labels (integers) by value, as the scan's contacts are (a < b); file names
    as text."""
    try:
        return (a, b) if a < b else (b, a)
    except TypeError:
        return (a, b) if str(a) < str(b) else (b, a)


def _scanPairs(contacts):
    if hasattr(contacts, 'a'):  # columns (ScanContacts): no dict a contact
        return list(zip(contacts.a.tolist(), contacts.b.tolist()))
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
        found = grainRecord(outdir, name[:-5])
        if found is None:
            raise ValueError('mssAssembly: %s: its record or files changed since the batch wrote them (or are not '
                             'a batch\'s): run the batch again' % os.path.join(g, name[:-5]))
        meta, r = found
        row = meta['row']
        if row['status'] == 'ok':
            out[row['label'] if row['label'] != '' else row['file']] = r
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
        tolerance = _tolerance(os.fspath(source))
        box = _scanBox(os.fspath(source))
    else:
        requireVoxelSize('mssAssembly', source, dict(voxelSize=voxelSize))
        b = batch(source if isinstance(source, np.ndarray) else [source], None, workers=1,
                  minVoxels=minVoxels, excludeBorder=excludeBorder, labels=labels, voxelSize=voxelSize,
                  origin=origin, progress=False, **gen)
        if b.failed:
            raise RuntimeError('mssAssembly: grains failed: %s' % '; '.join(
                '%s: %s' % (k, b.rows[k]['message']) for k in b.failed[:5]))
        results = {b.rows[k]['label']: r for k, r in b.results.items()}
        contacts = b.scanContacts or []
        tolerance = gen.get('contactGap', 1.0)
        box = getattr(b, 'scanBox', None)
    utils, O, me = yadeModules()
    out = {}
    try:
        for key, r in results.items():
            m = r.targetMass
            out[key] = buildClump(r.centers, r.radii, m.volume, m.centroid, m.inertia, body)
    except Exception:
        for cid, ids in out.values():
            O.bodies.erase(cid, True)
        raise
    if box is not None:  # porosity()'s default container: the scan's box, not the spheres' (1.5 voxels beyond it)
        O.tags[SCAN_BOX_TAG] = json.dumps(box)
    h = next(iter(results.values())).grid['voxelSize'] if results else 1.0
    return Assembly(out, _scanPairs(contacts), tolerance * h)


def _scanBox(outdir):
    """The world box of a finished batch's labelled volume, [lower, upper], from its manifest; None (a folder of
    grains, or an older manifest)."""
    try:
        box = _manifest.read(outdir)['state']['scanBox']
        return [[float(x) for x in box[0]], [float(x) for x in box[1]]] if box is not None else None
    except (ValueError, KeyError, TypeError, IndexError):
        return None


def _tolerance(outdir):
    """The contact gap (voxels) a finished batch counted its scan's contacts with: its manifest's, or the
    default."""
    try:
        return float(_manifest.read(outdir)['state']['contacts']['gap'])
    except (ValueError, KeyError, TypeError):
        return 1.0
