"""Voxel volumes: read (.npy, .tif), labelled volumes cut into regions, binary scans segmented into grains.

Convention, as everywhere in the project: array element [i, j, k] is the voxel whose centre is at
origin + h (i, j, k). A TIFF stack is taken in the order tifffile gives (pages first).
"""

import os

import numpy as np

from .. import _mss
from ..base import integer, number, readNpy, readTiff

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


SLAB_VOXELS = 1 << 23  # findContacts reads the volume in slabs of about this many voxels (64 MB as int64)


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
    if only is not None and (isinstance(only, (str, bytes)) or not isinstance(only, (list, tuple, set, np.ndarray))):
        raise TypeError('regions: only must be a list of integers, got %r' % (only,))  # '12' is not [1, 2]
    wanted = None if only is None else set(integer('regions', 'only', x, 0, None) for x in only)
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
