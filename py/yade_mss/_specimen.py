"""Specimens: labelled volumes read and cut into grains, and synthetic specimens for tests and benchmarks.

Convention, as everywhere in the project: array element [i, j, k] is the voxel whose centre is at
origin + h (i, j, k). A TIFF stack is taken in the order tifffile gives (pages first).
"""

import math
import os

import numpy as np

from . import _mss
from ._args import INT64_MAX, integer, number
from ._clumps import randomRotation
from ._files import readNpy, readTiff

_VOLUME_EXT = tuple(f['extension'] for f in _mss.fileFormats() if f['kind'] == 'voxels')  # the format table's


def readVolume(path):
    """An integer or boolean volume from a .npy file or a TIFF stack. Raises ValueError naming the problem."""
    path = os.fspath(path)
    ext = os.path.splitext(path)[1].lower()
    if ext == '.npy':
        a = readNpy('readVolume', path, mmap=True)
    elif ext in ('.tif', '.tiff'):
        a = readTiff('readVolume', path)
    else:
        raise ValueError("readVolume: %s: unknown volume extension '%s' (expected .npy, .tif or .tiff)"
                         % (path, ext))
    if a.ndim != 3:
        raise ValueError('readVolume: %s: the volume must be 3-D, got %d-D' % (path, a.ndim))
    if not (a.dtype == bool or np.issubdtype(a.dtype, np.integer)):
        raise ValueError('readVolume: %s: dtype %s is not boolean or integer (a labelled volume: 0 is background)'
                         % (path, a.dtype))
    return np.asarray(a)


class Region(object):
    """One label of a volume: its bounding box (slices), voxel count, and whether it touches the border."""

    def __init__(self, label, box, voxels, shape):
        self.label = int(label)
        self.box = box
        self.voxels = int(voxels)
        self.touchesBorder = any(s.start == 0 or s.stop == n for s, n in zip(box, shape))

    def crop(self, labels, pad=2):
        """The label's voxels in its box, padded by *pad* empty voxels (the double zero hull, eq. 6), and the
        index of the crop's voxel (0, 0, 0) in the volume."""
        sub = labels[self.box] == self.label
        start = np.array([s.start for s in self.box]) - pad
        return np.pad(sub, pad), start

    def neighbours(self, labels, pad=2):
        """The other grains on the grid of :meth:`crop` (booleans): where no sphere may protrude by more than half
        the bound."""
        lo = [max(0, s.start - pad) for s in self.box]
        hi = [min(n, s.stop + pad) for s, n in zip(self.box, labels.shape)]
        sub = labels[tuple(slice(a, b) for a, b in zip(lo, hi))]
        widths = [(a - (s.start - pad), s.stop + pad - b) for a, b, s in zip(lo, hi, self.box)]
        return np.pad((sub != 0) & (sub != self.label), widths)  # beyond the volume: nobody


def slabVoxels(memoryLimit=None):
    """How many voxels a slab of the volume holds when read a slab at a time: SLAB_VOXELS, or less where
    *memoryLimit* (GiB, generate's option) is lower: a slab costs about 24 bytes a voxel as it is read and
    converted, up to 48 for the sparse boxes, so a 128th of the limit keeps the batch well under it."""
    if memoryLimit is None:
        return SLAB_VOXELS
    return int(max(1 << 12, min(SLAB_VOXELS, float(memoryLimit) * (1 << 30) / 128)))


def regions(labels, only=None, memoryLimit=None):
    """The labels present (non-zero), each as a :class:`Region`, in increasing label order: one pass over the
    volume (``scipy.ndimage.find_objects``), then each label counted in its own box.

    :param labels: a 3-D array of integers >= 0 (0 is background), or of booleans
    :param only: these labels only, a list of integers (default: all)
    :param memoryLimit: GiB, as generate's option: bounds the slabs where the volume is read by slabs
    :return: list of :class:`Region` (label, box, voxels, touchesBorder)
    """
    from scipy import ndimage
    labels = np.asarray(labels)
    if labels.ndim != 3 or not (labels.dtype == bool or np.issubdtype(labels.dtype, np.integer)):
        raise ValueError('regions: labels must be a 3-D array of integers, got %s of %s' % (labels.shape, labels.dtype))
    if labels.dtype == bool:
        labels = labels.view(np.uint8)  # a view: a memory-mapped volume stays on disk
    if labels.min() < 0:
        raise ValueError('labels must be >= 0 (0 is background), found %d' % labels.min())
    top = int(labels.max()) if labels.size else 0
    wanted = None if only is None else set(int(x) for x in only)
    out = []
    if top <= max(DENSE_LABELS, labels.size // 64) and labels.dtype.isnative and labels.flags.aligned:
        boxes = enumerate(ndimage.find_objects(labels), 1)
    else:  # find_objects' list has an entry per label up to the largest (2^40: a MemoryError), and it copies a
        # swapped or unaligned volume whole
        boxes = _sparseBoxes(labels, slabVoxels(memoryLimit))
    for label, box in boxes:
        if box is None or (wanted is not None and label not in wanted):
            continue
        out.append(Region(label, box, np.count_nonzero(labels[box] == label), labels.shape))
    if wanted is not None:
        missing = sorted(wanted - set(r.label for r in out))
        if missing:
            raise ValueError('labels not in the volume: %s' % ', '.join(str(m) for m in missing))
    return out


DENSE_LABELS = 1 << 20  # labels up to this (or a 64th of the voxels) are boxed by find_objects


def _sparseBoxes(labels, voxels):
    """(label, box) of every label present, in increasing order, by slabs of the volume: memory follows the
    labels present and one slab, not the largest label."""
    lo, hi = {}, {}
    layers = max(1, voxels // max(1, labels.shape[1] * labels.shape[2]))
    for x0 in range(0, labels.shape[0], layers):
        s = np.asarray(labels[x0:x0 + layers])
        idx = np.flatnonzero(s)
        if not idx.size:
            continue
        present, inverse = np.unique(s.ravel()[idx], return_inverse=True)
        ijk = np.column_stack(np.unravel_index(idx, s.shape)) + (x0, 0, 0)
        first = np.full((present.size, 3), np.iinfo(np.int64).max)
        last = np.full((present.size, 3), -1)
        np.minimum.at(first, inverse, ijk)
        np.maximum.at(last, inverse, ijk)
        for label, f, l in zip(present.tolist(), first, last):
            lo[label] = np.minimum(lo.get(label, f), f)
            hi[label] = np.maximum(hi.get(label, l), l)
    for label in sorted(lo):
        yield label, tuple(slice(int(a), int(b) + 1) for a, b in zip(lo[label], hi[label]))


SLAB_VOXELS = 1 << 23  # findContacts reads the volume in slabs of about this many voxels (64 MB as int64)


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
    layers = max(1, slabVoxels(memoryLimit) // max(1, a.shape[1] * a.shape[2]))

    def read(x0, x1):
        s = np.asarray(a[x0:x1])
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


def voronoiBall(radius=50, cells=12, seed=1, lines=False):
    """A dense specimen: a ball of *radius* voxels cut into *cells* Voronoi cells (labels 1..cells), every grain
    touching its neighbours: for tests and benchmarks of contacts.

    :param int radius: the ball's radius, voxels
    :param int cells: how many cells (grains)
    :param int seed: random seed of the cells' seeds
    :param bool lines: separate the cells by a line of background voxels, as a watershed segmentation does
        (a cell's voxel beside one of a higher label is cleared): no two grains share a face
    :return: int32 array of (2 radius + 5)^3 voxels, labels 1..cells
    """
    from scipy.spatial import cKDTree
    radius = integer('voronoiBall', 'radius', radius, 2, 1000)
    cells = integer('voronoiBall', 'cells', cells, 1, 100000)
    rng = np.random.default_rng(integer('voronoiBall', 'seed', seed, 0, INT64_MAX))
    n = 2 * radius + 5
    centre = (n - 1) / 2.0
    seeds = []
    while len(seeds) < cells:  # seeds in the inner 80% of the ball, so that no cell is a sliver of its rim
        p = rng.uniform(-0.8 * radius, 0.8 * radius, 3)
        if np.linalg.norm(p) <= 0.8 * radius:
            seeds.append(p + centre)
    g = np.indices((n, n, n)).reshape(3, -1).T.astype(float)
    inside = np.linalg.norm(g - centre, axis=1) <= radius
    labels = np.zeros(n ** 3, dtype=np.int32)
    labels[inside] = cKDTree(np.array(seeds)).query(g[inside])[1] + 1
    labels = labels.reshape(n, n, n)
    return separated(labels) if lines else labels


def separated(labels):
    """*labels* with a line of background between grains that share faces, as a segmentation with watershed lines
    draws them: a voxel beside (across a face) a voxel of a higher label is cleared."""
    out = np.array(labels, copy=True)
    for axis in range(3):
        for step in (1, -1):
            there = np.roll(labels, -step, axis=axis)
            edge = [slice(None)] * 3
            edge[axis] = -1 if step == 1 else 0  # np.roll wraps around: nothing beyond the volume
            there[tuple(edge)] = 0
            out[(labels != 0) & (there > labels)] = 0
    return out


def packedSpecimen(shape=(60, 60, 60), grains=30, size=(4, 8), seed=1, lines=True):
    """A dense specimen segmented as real pipelines do: overlapping balls packed at random (a grain's ball
    overlaps its neighbours'), their union's distance transform, a marker at each ball's centre and a marker
    watershed of the negated transform, with watershed lines (*lines*: a line of background voxels between
    touching grains, as ``skimage.segmentation.watershed(..., watershed_line=True)`` draws it).

    :param shape: the volume's size, 3 integers (voxels)
    :param int grains: how many balls
    :param size: the range of their radii, voxels
    :param int seed: random seed
    :param bool lines: separate touching grains by watershed lines
    :return: int32 array, labels 1..n (a ball swallowed by its neighbours may leave no grain)
    """
    from scipy import ndimage
    from skimage.segmentation import watershed
    func = 'packedSpecimen'
    if isinstance(shape, (str, bytes)) or not hasattr(shape, '__len__') or len(shape) != 3:
        raise TypeError('%s: shape must be 3 integers, got %r' % (func, shape))
    shape = tuple(integer(func, 'shape', n, 8, 4096) for n in shape)
    if shape[0] * shape[1] * shape[2] > 1 << 31:
        raise ValueError('%s: shape %r holds over 2^31 voxels' % (func, shape))
    grains = integer(func, 'grains', grains, 1, 10 ** 7)
    if isinstance(size, (str, bytes)) or not hasattr(size, '__len__') or len(size) != 2:
        raise TypeError('%s: size must be (smallest, largest) radius in voxels, got %r' % (func, size))
    lo, hi = (number(func, 'size', v, 1.0) for v in size)
    if lo > hi:
        raise ValueError('%s: size must be (smallest, largest), got %r' % (func, size))
    rng = np.random.default_rng(integer(func, 'seed', seed, 0, INT64_MAX))
    radii = rng.uniform(lo, hi, grains)
    # centres spread over the volume, each ball overlapping some (a dense packing's necks)
    centres = rng.uniform(0, 1, (grains, 3)) * (np.array(shape) - 1)
    solid = np.zeros(shape, dtype=bool)
    markers = np.zeros(shape, dtype=np.int32)
    for n, (c, r) in enumerate(zip(centres, radii), 1):
        box = tuple(slice(max(0, int(c[d] - r - 1)), min(shape[d], int(c[d] + r + 2))) for d in range(3))
        grid = np.stack(np.meshgrid(*[np.arange(s.start, s.stop) for s in box], indexing='ij'), axis=-1)
        solid[box] |= ((grid - c) ** 2).sum(axis=-1) <= r * r
    for n, c in enumerate(centres, 1):
        markers[tuple(int(round(x)) for x in c)] = n
    markers[~solid] = 0
    dist = ndimage.distance_transform_edt(solid)
    labels = watershed(-dist, markers, mask=solid, watershed_line=bool(lines)).astype(np.int32)
    # labels 1..n in order, none missing (a marker inside another ball's core may have lost its voxels)
    present = np.unique(labels[labels != 0])
    table = np.zeros(int(labels.max()) + 1, dtype=np.int32)
    table[present] = np.arange(1, present.size + 1, dtype=np.int32)
    return table[labels]


def syntheticSpecimen(shape=(160, 160, 160), grains=40, size=(7, 14), seed=1, gap=1, maxTries=20000):
    """A labelled volume of random, non-overlapping, randomly oriented irregular grains (each the union of two
    or three ellipsoids), some cut by the volume's border: for tests and benchmarks.

    :param shape: the volume's size, 3 integers (voxels)
    :param int grains: how many grains to place
    :param size: range of the ellipsoids' semi-axes, voxels
    :param int seed: random seed
    :param int gap: least number of empty voxels between two grains
    :param int maxTries: placements tried before giving up on more grains
    :return: int32 array, labels 1..n (n may fall short of *grains* if they do not fit)
    """
    func = 'syntheticSpecimen'
    if isinstance(shape, (str, bytes)) or not hasattr(shape, '__len__') or len(shape) != 3:
        raise TypeError('%s: shape must be 3 integers, got %r' % (func, shape))
    shape = tuple(integer(func, 'shape', n, 1) for n in shape)
    if shape[0] * shape[1] * shape[2] > 1 << 31:
        raise ValueError('%s: shape %r holds over 2^31 voxels' % (func, shape))
    grains = integer(func, 'grains', grains, 1)
    if isinstance(size, (str, bytes)) or not hasattr(size, '__len__') or len(size) != 2:
        raise TypeError('%s: size must be (smallest, largest) semi-axis in voxels, got %r' % (func, size))
    lo, hi = (number(func, 'size', v, 0.5) for v in size)
    if lo > hi:
        raise ValueError('%s: size must be (smallest, largest), got %r' % (func, size))
    gap = integer(func, 'gap', gap, 0)
    maxTries = integer(func, 'maxTries', maxTries, 1)
    rng = np.random.default_rng(integer(func, 'seed', seed, 0, INT64_MAX))
    labels = np.zeros(shape, dtype=np.int32)
    grown = np.zeros(shape, dtype=bool)  # grains dilated by the gap: where no new grain may go
    placed = 0
    for _ in range(maxTries):
        if placed == grains:
            break
        R = randomRotation(rng)
        parts = [(np.zeros(3), rng.uniform(lo, hi, 3))]
        for _ in range(rng.integers(1, 3)):
            parts.append((R.dot(rng.normal(0, 0.6 * lo, 3)), rng.uniform(0.6 * lo, 0.9 * hi, 3)))
        reach = int(math.ceil(max(np.linalg.norm(c) + a.max() for c, a in parts))) + gap
        centre = rng.uniform(0, np.array(shape))  # grains near a face are cut by it
        box = [slice(max(0, int(centre[d]) - reach), min(shape[d], int(centre[d]) + reach + 1)) for d in range(3)]
        if any(s.stop - s.start < 2 for s in box):
            continue
        grid = np.stack(np.meshgrid(*[np.arange(s.start, s.stop) for s in box], indexing='ij'), axis=-1) - centre
        local = grid.dot(R)  # coordinates in the grain's frame
        inside = np.zeros(grid.shape[:3], dtype=bool)
        near = np.zeros(grid.shape[:3], dtype=bool)
        for c, a in parts:
            q = (((local - c) / a) ** 2).sum(axis=-1)
            inside |= q <= 1.0
            near |= (((local - c) / (a + gap)) ** 2).sum(axis=-1) <= 1.0
        if inside.sum() < 50 or (grown[tuple(box)] & near).any():
            continue
        placed += 1
        labels[tuple(box)][inside] = placed
        grown[tuple(box)] |= near
    return labels


def binaryValue(labels, memoryLimit=None):
    """The one non-zero value of a volume that holds two (0 and it: a thresholded scan), or None (labels, or
    nothing but background). Read in slabs: a memory-mapped volume stays on disk."""
    a = labels if isinstance(labels, np.ndarray) else np.asarray(labels)
    if a.dtype == bool:
        return 1 if a.any() else None
    layers = max(1, slabVoxels(memoryLimit) // max(1, a.shape[1] * a.shape[2]))
    value = None
    for x0 in range(0, a.shape[0], layers):
        s = np.asarray(a[x0:x0 + layers])
        nz = s[s != 0]
        if not nz.size:
            continue
        lo, hi = nz.min(), nz.max()
        if lo != hi or (value is not None and lo != value):
            return None
        value = lo
    return None if value is None else int(value)


def pieces(labels):
    """How many separate pieces (face-connected) the non-zero voxels of a volume form."""
    from scipy import ndimage
    return int(ndimage.label(np.asarray(labels) != 0)[1])


def segmentBinary(binary, h=1.0):
    """A binary scan cut into grains as the usual pipeline does: the Euclidean distance transform of the solid,
    a marker at each of its maxima that stands at least *h* voxels above the saddles around it (h-maxima), and
    a marker watershed of the negated transform inside the solid. A piece with no such maximum (thinner than
    *h*) is a grain of its own. Labels 1..n, no separating lines (grains touch where they meet).

    :param binary: a 3-D array, non-zero where the solid is
    :param float h: the markers' least height, voxels (larger: fewer, larger grains)
    :return: int32 array of labels, 0 the background
    """
    from scipy import ndimage
    from skimage.morphology import h_maxima
    from skimage.segmentation import watershed
    h = number('segment', 'segmentH', h, 0.0)
    solid = np.asarray(binary) != 0
    if solid.ndim != 3:
        raise ValueError('segment: the scan must be 3-D, got %d-D' % solid.ndim)
    dist = ndimage.distance_transform_edt(solid)
    markers, n = ndimage.label(h_maxima(dist, h))
    labels = watershed(-dist, markers, mask=solid).astype(np.int32)
    rest, m = ndimage.label(solid & (labels == 0))
    labels[rest != 0] = rest[rest != 0] + n
    return labels
