"""Contacts in a labelled scan: every pair of grains that touch (or nearly: across a watershed line), with a
point and a normal for each, the points a grain's spheres must keep reaching when it is generated."""

import numpy as np

from .. import _mss
from ..base import number, optional, vector3
from ._volumes import slab, slabVoxels


def findContacts(labels, voxelSize=1.0, origin=(0.0, 0.0, 0.0), memoryLimit=None, gap=1.0):
    """Every pair of grains in contact in the scan, found once for the whole volume: grains whose voxels share
    faces (*gap* 0) or come within *gap* voxels of each other (the default, one voxel, covers the separating
    lines of a marker watershed and the labels of a thresholded scan). A list of dicts ``a``, ``b`` (a < b),
    ``faces`` (the voxel pairs within the tolerance: shared faces with a gap of 0), ``gap`` (the least gap
    between the two grains' voxel cubes, voxels), ``point`` (the midpoint of a closest pair nearest the centroid
    of them all, world units: on a shared face, or the middle of a separating line) and ``normal`` (from a into
    b). The volume is read in slabs (a memory-mapped .npy stays on disk but for one slab).

    :param labels: a 3-D array of integers >= 0 (0 is background), or of booleans
    :param float voxelSize: the voxel edge, world units
    :param origin: the world position of the centre of voxel (0, 0, 0)
    :param memoryLimit: GiB, as generate's option: the slabs are a 128th of it at most (:func:`slabVoxels`)
    :param float gap: the contact tolerance, voxels, in [0, 8]: the gap between two grains' voxel cubes up to
        which they count as in contact; 0: shared faces only
    """
    a = labels if isinstance(labels, np.ndarray) else np.asarray(labels)
    if a.ndim != 3 or not (a.dtype == bool or np.issubdtype(a.dtype, np.integer)):
        raise ValueError('findContacts: labels must be a 3-D array of integers, got %s of %s' % (a.shape, a.dtype))
    gap = number('findContacts', 'gap', gap, 0.0, 8.0)
    voxelSize = number('findContacts', 'voxelSize', voxelSize)
    if not voxelSize > 0:
        raise ValueError('findContacts: voxelSize must be > 0, got %r' % (voxelSize,))
    origin = vector3('findContacts', 'origin', origin)
    memoryLimit = optional(number, 'findContacts', 'memoryLimit', memoryLimit, 0.0)
    layers = max(1, slabVoxels(memoryLimit) // max(1, a.shape[1] * a.shape[2]))

    def read(x0, x1):
        s = slab(a, x0, x1)
        if s.dtype == np.uint64 and s.size and s.max() > np.iinfo(np.int64).max:
            raise ValueError('findContacts: a label over 2^63 - 1')
        return np.asfortranarray(s, dtype=np.int64).tobytes(order='F')
    return _mss.findContacts(read, tuple(int(n) for n in a.shape), float(voxelSize), [float(x) for x in origin],
                             layers, gap)


NEARBY_GAP = 3.0  # voxels: where no two grains are within the tolerance, the gaps looked at to say why


class ScanContacts(list):
    """:func:`findContacts`' list for a batch, with the tolerance it used (*gap*, voxels) and, where it found no
    pair, *nearby*: the least gaps (voxels) of the pairs of grains within NEARBY_GAP voxels, the report's why."""

    def __init__(self, contacts, gap, nearby=None):
        list.__init__(self, contacts)
        self.gap, self.nearby = gap, nearby


def scanContacts(labels, voxelSize, origin, memoryLimit, gap):
    """:class:`ScanContacts` of a labelled volume: findContacts at *gap*, and where it finds none (and the
    tolerance is under NEARBY_GAP) the gaps between the grains that are near each other all the same."""
    found = findContacts(labels, voxelSize, origin, memoryLimit, gap)
    nearby = None
    if not found and gap < NEARBY_GAP:
        nearby = sorted(c['gap'] for c in findContacts(labels, voxelSize, origin, memoryLimit, NEARBY_GAP))
    return ScanContacts(found, gap, nearby)


def contactPoints(contacts, label):
    """The points a grain's spheres must reach, 6 numbers each (the point, the normal into the grain), from
    :func:`findContacts`'s list: what :func:`generate` takes for a labelled volume's grain."""
    return contactsByLabel(contacts).get(int(label), [])


def contactsByLabel(contacts):
    """:func:`contactPoints` of every label at once, {label: points}: one pass over the contacts (a batch asking
    each grain in turn would pass over them once per grain)."""
    out = {}
    for c in contacts:
        out.setdefault(c['a'], []).append(list(c['point']) + [-x for x in c['normal']])
        out.setdefault(c['b'], []).append(list(c['point']) + list(c['normal']))
    return out
