"""Voxel volumes: read (.npy, .tif), labelled volumes cut into regions, binary scans segmented into grains.

Convention, as everywhere in the project: array element [i, j, k] is the voxel whose centre is at
origin + h (i, j, k). A TIFF stack is taken in the order tifffile gives (pages first).
"""

import os

import numpy as np

from .. import _mss
from ..base import integer, number, optional, readNpy, readTiff

VOLUME_EXT = tuple(f['extension'] for f in _mss.fileFormats() if f['kind'] == 'voxels')  # the format table's


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
    if a.size > MAX_VOXELS:  # said at once, before any pass over the scan (each a read of the whole file)
        raise ValueError('readVolume: %s: %s voxels (%d), over the %d (2^31 - 1) a grid can index; crop the scan '
                         'or coarsen it' % (path, 'x'.join(str(n) for n in a.shape), a.size, MAX_VOXELS))
    return np.asarray(a)


MAX_VOXELS = 2147483647  # the C++ grids' index (mss::checkGridSize)


def _mapping(a):
    """The mmap under a memory-mapped volume (a .npy or an uncompressed TIFF read by :func:`readVolume`), or None."""
    while a is not None:
        m = getattr(a, '_mmap', None)
        if m is not None:
            return m
        a = getattr(a, 'base', None)
    return None


def release(a):
    """Hands the pages of a memory-mapped volume that this process has read back to the kernel (they stay in the
    page cache, and are read from it again when needed): a pass over an 8 GB scan would otherwise count all 8 GB
    in the process's resident memory, over any --memory-limit."""
    import mmap
    m = _mapping(a)
    if m is not None and hasattr(mmap, 'MADV_DONTNEED'):
        try:
            m.madvise(mmap.MADV_DONTNEED)
        except (OSError, ValueError):  # a closed map, a kernel without it: only the resident count suffers
            pass


def slab(a, x0, x1):
    """Layers x0 .. x1 - 1 of a volume as an array of its own, the mapping's pages released (:func:`release`)."""
    s = np.array(a[x0:x1])
    release(a)
    return s


class Region(object):
    """One label of a volume: its bounding box (slices), voxel count, and whether it touches the border."""

    __slots__ = ('label', 'box', 'voxels', 'touchesBorder')  # a batch holds one a grain: 10^5 and more

    def __init__(self, label, box, voxels, shape):
        self.label = int(label)
        self.box = box
        self.voxels = int(voxels)
        self.touchesBorder = any(s.start == 0 or s.stop == n for s, n in zip(box, shape))

    def crop(self, labels, pad=2):
        """The label's voxels in its box, padded by *pad* empty voxels (the double zero hull, eq. 6), and the
        index of the crop's voxel (0, 0, 0) in the volume."""
        start = np.array([s.start for s in self.box]) - pad
        return self.cut(labels, pad, False)[0], start

    def cut(self, labels, pad=2, neighbours=True):
        """:meth:`crop`'s voxels and (with *neighbours*) :meth:`neighbours`', from one read of the box and its
        margin: (crop, neighbours or None). Into zeroed arrays, not np.pad (a tenth of a millisecond a grain,
        seconds for a scan's 10^4 grains)."""
        lo = [max(0, s.start - pad) for s in self.box]
        hi = [min(n, s.stop + pad) for s, n in zip(self.box, labels.shape)]
        sub = np.asarray(labels[tuple(slice(a, b) for a, b in zip(lo, hi))])
        _CUTS[0] += 1
        if _CUTS[0] % RELEASE_CUTS == 0:  # a grain's pages are a few hundred kB: handed back now and then
            release(labels)
        shape = tuple(s.stop - s.start + 2 * pad for s in self.box)
        into = tuple(slice(a - (s.start - pad), b - (s.start - pad)) for a, b, s in zip(lo, hi, self.box))
        mine = sub == self.label
        crop = np.zeros(shape, dtype=bool)
        inner = tuple(slice(s.start - a, s.stop - a) for s, a in zip(self.box, lo))  # the box itself
        crop[tuple(slice(pad, pad + s.stop - s.start) for s in self.box)] = mine[inner]
        near = None
        if neighbours:
            near = np.zeros(shape, dtype=bool)  # beyond the volume: nobody
            near[into] = (sub != 0) & ~mine
        return crop, near

    def neighbours(self, labels, pad=2):
        """The other grains on the grid of :meth:`crop` (booleans): where no sphere may protrude by more than half
        the bound."""
        return self.cut(labels, pad)[1]


RELEASE_CUTS = 32  # grains cut between two hand-backs of a mapped scan's pages (each a madvise and faults)
_CUTS = [0]

SLAB_VOXELS = 1 << 23  # findContacts reads the volume in slabs of about this many voxels (64 MB as int64)


def slabVoxels(memoryLimit=None):
    """How many voxels a slab of the volume holds when read a slab at a time: SLAB_VOXELS, or less where
    *memoryLimit* (GiB, generate's option) is lower: a slab costs about 24 bytes a voxel as it is read and
    converted (32 in the contact search, with its edges' labels), up to 48 for the sparse boxes, so a 128th of
    the limit keeps the batch well under it."""
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
    memoryLimit = optional(number, 'regions', 'memoryLimit', memoryLimit, 0.0)
    labels = np.asarray(labels)
    if labels.ndim != 3 or not (labels.dtype == bool or np.issubdtype(labels.dtype, np.integer)):
        raise ValueError('regions: labels must be a 3-D array of integers, got %s of %s' % (labels.shape, labels.dtype))
    if labels.dtype == bool:
        labels = labels.view(np.uint8)  # a view: a memory-mapped volume stays on disk
    low, top = valueRange(labels, slabVoxels(memoryLimit))
    if low < 0:
        raise ValueError('labels must be >= 0 (0 is background), found %d' % low)
    if only is not None and (isinstance(only, (str, bytes)) or not isinstance(only, (list, tuple, set, np.ndarray))):
        raise TypeError('regions: only must be a list of integers, got %r' % (only,))  # '12' is not [1, 2]
    wanted = None if only is None else set(integer('regions', 'only', x, 0, None) for x in only)
    out = []
    mapped = _mapping(labels) is not None
    if top <= max(DENSE_LABELS, labels.size // 64) and labels.dtype.isnative and labels.flags.aligned and not mapped:
        boxes = enumerate(ndimage.find_objects(labels), 1)
    elif top <= DENSE_LABELS:  # a mapped scan: by slabs, so that its pages are released as they are read
        boxes = _slabBoxes(labels, slabVoxels(memoryLimit))
    else:  # find_objects' list has an entry per label up to the largest (2^40: a MemoryError), and it copies a
        # swapped or unaligned volume whole
        boxes = _sparseBoxes(labels, slabVoxels(memoryLimit))
    counts = None
    if top <= DENSE_LABELS:  # every label's voxels in one pass by slabs (a count in each box cost 0.1 ms a label)
        counts = np.zeros(int(top) + 1, dtype=np.int64)
        layers = max(1, slabVoxels(memoryLimit) // max(1, labels.shape[1] * labels.shape[2]))
        for x0 in range(0, labels.shape[0], layers):
            counts += np.bincount(slab(labels, x0, x0 + layers).ravel(), minlength=len(counts))
    for label, box in boxes:
        if box is None or (wanted is not None and label not in wanted):
            continue
        if counts is not None:
            out.append(Region(label, box, counts[label], labels.shape))
            continue
        out.append(Region(label, box, np.count_nonzero(labels[box] == label), labels.shape))
        release(labels)
    if wanted is not None:
        missing = sorted(wanted - set(r.label for r in out))
        if missing:
            raise ValueError('labels not in the volume: %s' % ', '.join(str(m) for m in missing))
    return out


DENSE_LABELS = 1 << 20  # labels up to this (or a 64th of the voxels) are boxed by find_objects


def valueRange(labels, voxels=SLAB_VOXELS):
    """(least, largest) value of a volume, read by slabs (0, 0 for an empty one)."""
    low, top = 0, 0
    layers = max(1, voxels // max(1, labels.shape[1] * labels.shape[2]))
    for x0 in range(0, labels.shape[0], layers):
        s = slab(labels, x0, x0 + layers)
        if s.size:
            low, top = min(low, int(s.min())), max(top, int(s.max()))
    return low, top


def _slabBoxes(labels, voxels):
    """(label, box) of every label present, in increasing order, by slabs and ``find_objects`` in each."""
    from scipy import ndimage
    lo, hi = {}, {}
    layers = max(1, voxels // max(1, labels.shape[1] * labels.shape[2]))
    for x0 in range(0, labels.shape[0], layers):
        for label, box in enumerate(ndimage.find_objects(slab(labels, x0, x0 + layers)), 1):
            if box is not None:
                f = (box[0].start + x0, box[1].start, box[2].start)
                l = (box[0].stop + x0, box[1].stop, box[2].stop)
                lo[label] = tuple(map(min, lo[label], f)) if label in lo else f
                hi[label] = tuple(map(max, hi[label], l)) if label in hi else l
    for label in sorted(lo):
        yield label, tuple(slice(a, b) for a, b in zip(lo[label], hi[label]))


def _sparseBoxes(labels, voxels):
    """(label, box) of every label present, in increasing order, by slabs of the volume: memory follows the
    labels present and one slab, not the largest label."""
    lo, hi = {}, {}
    layers = max(1, voxels // max(1, labels.shape[1] * labels.shape[2]))
    for x0 in range(0, labels.shape[0], layers):
        s = slab(labels, x0, x0 + layers)
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


def binaryValue(labels, memoryLimit=None):
    """The one non-zero value of a volume that holds two (0 and it: a thresholded scan), or None (labels, or
    nothing but background). Read in slabs: a memory-mapped volume stays on disk."""
    a = labels if isinstance(labels, np.ndarray) else np.asarray(labels)
    if a.dtype == bool:
        return 1 if a.any() else None
    layers = max(1, slabVoxels(memoryLimit) // max(1, a.shape[1] * a.shape[2]))
    value = None
    for x0 in range(0, a.shape[0], layers):
        s = slab(a, x0, x0 + layers)
        nz = s[s != 0]
        if not nz.size:
            continue
        lo, hi = nz.min(), nz.max()
        if lo != hi or (value is not None and lo != value):
            return None
        value = lo
    return None if value is None else int(value)


def pieces(labels, memoryLimit=None):
    """How many separate pieces (face-connected) the non-zero voxels of a volume form. Read in slabs (a
    memory-mapped volume stays on disk; a whole-volume label array is 4-8 bytes a voxel): each slab labelled
    alone, then the pieces that meet across two slabs' common face joined (union-find)."""
    from scipy import ndimage
    a = labels if isinstance(labels, np.ndarray) else np.asarray(labels)
    if a.ndim != 3:
        raise ValueError('pieces: the volume must be 3-D, got %d-D' % a.ndim)
    layers = max(1, slabVoxels(memoryLimit) // max(1, a.shape[1] * a.shape[2]))
    parent = np.zeros(1, np.int64)  # parent[i] of piece i (global ids from 1; 0 is background)
    total, last = 0, None

    def root(i):
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    for x0 in range(0, a.shape[0], layers):
        lab, k = ndimage.label(slab(a, x0, x0 + layers) != 0)
        lab = np.where(lab > 0, lab + total, 0)
        parent = np.concatenate([parent, np.arange(total + 1, total + k + 1)])
        if last is not None:
            touch = (last > 0) & (lab[0] > 0)
            for p, q in np.unique(np.column_stack([last[touch], lab[0][touch]]), axis=0).tolist():
                rp, rq = root(p), root(q)
                if rp != rq:
                    parent[max(rp, rq)] = min(rp, rq)
        last = lab[-1].copy()
        total += k
    return int(sum(1 for i in range(1, total + 1) if root(i) == i))
