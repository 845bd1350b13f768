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
    return list(_columns(labels, voxelSize, origin, memoryLimit, gap))


def _columns(labels, voxelSize=1.0, origin=(0.0, 0.0, 0.0), memoryLimit=None, gap=1.0):
    """:func:`findContacts` as :class:`ScanContacts` (columns: a batch of 10^5 grains holds 10^6 contacts)."""
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
    return ScanContacts(_mss.findContacts(read, tuple(int(n) for n in a.shape), float(voxelSize),
                                          [float(x) for x in origin], layers, gap), gap)


NEARBY_GAP = 3.0  # voxels: where no two grains are within the tolerance, the gaps looked at to say why


class ScanContacts(object):
    """:func:`findContacts`' contacts as columns (numpy arrays, one entry a contact: ``a``, ``b``, ``faces``,
    ``gaps``, ``points`` (n, 3), ``normals`` (n, 3)), with the tolerance it used (*gap*, voxels) and, where it
    found no pair, *nearby*: the least gaps (voxels) of the pairs of grains within NEARBY_GAP voxels, the
    report's why. Indexing or iterating gives findContacts' dicts, one at a time.

    :param columns: a dict of those columns (arrays, or the bytes of int64 and double arrays as the core gives)
    """

    COLUMNS = (('a', 'a', np.int64, 1), ('b', 'b', np.int64, 1), ('faces', 'faces', np.int64, 1),
               ('gaps', 'gap', np.float64, 1), ('points', 'point', np.float64, 3),
               ('normals', 'normal', np.float64, 3))

    def __init__(self, columns, gap, nearby=None):
        for name, key, dtype, width in self.COLUMNS:
            v = columns[key] if key in columns else columns[name]
            v = np.frombuffer(v, dtype=dtype) if isinstance(v, bytes) else np.asarray(v, dtype=dtype)
            setattr(self, name, v.reshape(-1, 3) if width == 3 else v.reshape(-1))
        self.gap, self.nearby = gap, nearby

    def __len__(self):
        return len(self.a)

    def __getitem__(self, i):
        return dict(a=int(self.a[i]), b=int(self.b[i]), faces=int(self.faces[i]), gap=float(self.gaps[i]),
                    point=tuple(float(x) for x in self.points[i]), normal=tuple(float(x) for x in self.normals[i]))

    def __iter__(self):
        return (self[i] for i in range(len(self)))

    @staticmethod
    def fromDicts(contacts, gap, nearby=None):
        """From findContacts' dicts (as a contacts.csv gives them back)."""
        c = list(contacts)
        return ScanContacts({'a': [x['a'] for x in c], 'b': [x['b'] for x in c],
                             'faces': [x['faces'] for x in c], 'gap': [x.get('gap', 0.0) for x in c],
                             'point': [x['point'] for x in c], 'normal': [x['normal'] for x in c]}, gap, nearby)


def scanContacts(labels, voxelSize, origin, memoryLimit, gap):
    """:class:`ScanContacts` of a labelled volume: findContacts at *gap*, and where it finds none (and the
    tolerance is under NEARBY_GAP) the gaps between the grains that are near each other all the same."""
    found = _columns(labels, voxelSize, origin, memoryLimit, gap)
    if not len(found) and gap < NEARBY_GAP:
        found.nearby = sorted(float(g) for g in _columns(labels, voxelSize, origin, memoryLimit, NEARBY_GAP).gaps)
    return found


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


class ContactIndex(object):
    """The points each grain of a scan must reach (:func:`contactPoints` of every label), from
    :class:`ScanContacts` as arrays: each contact's two ends (its point with the normal into a, then into b)
    ordered by label, and each label's run of them found by bisection; a grain's points are made when it
    asks, so that a batch holds none of them but for the grains in flight (12 bytes an end, not 56)."""

    def __init__(self, contacts, keep=None):
        """*keep*: a boolean a contact, those to index (default: all); the contacts are not copied."""
        n = len(contacts)
        kept = np.arange(n) if keep is None else np.flatnonzero(keep)
        labels = np.concatenate([contacts.a[kept], contacts.b[kept]])
        ends = np.concatenate([kept, kept + n])  # an end: a contact's number, plus n for its b side
        # by label, then in the contacts' order: the points in the order contactsByLabel gives them (a grain's
        # input digest, and the order the core takes them in, as before)
        order = np.lexsort((np.concatenate([kept, kept]), labels))
        self._contacts, self._labels = contacts, labels[order]
        self._order = ends[order].astype(np.int32 if 2 * n < 2 ** 31 else np.int64)

    def __call__(self, label):
        """The grain's points, an (n, 6) array (point, normal into the grain)."""
        lo = int(self._labels.searchsorted(label))
        hi = int(self._labels.searchsorted(label, 'right'))
        ends = self._order[lo:hi]
        n = len(self._contacts)
        c = ends % n
        out = np.empty((hi - lo, 6))
        out[:, :3] = self._contacts.points[c]
        out[:, 3:] = self._contacts.normals[c]
        out[ends < n, 3:] *= -1.0  # into a: against the normal, which points from a to b
        return out
