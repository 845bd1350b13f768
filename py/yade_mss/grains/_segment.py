"""Binary scans cut into grains (``mss batch --segment``): a thresholded micro-CT of touching, porous grains with
noise specks, as real scans are, to labels 1..n of its grains.

The usual pipeline (distance transform, h-maxima markers, marker watershed) at a fixed height h shatters
porous grains: every pore dents the transform and every dent makes a maximum (a real carbonate-sand scan gave
6,479 segments for 34 grains at h = 1), while an h large enough to join them joins touching grains too, and
the right h follows the grains' size. Here, at the defaults, nothing is in voxels:

1. specks (solid pieces under SPECK_VOXELS) are dropped; pores that the solid encloses are filled, and
   open ones closed by a ball of CLOSE_FRACTION of the typical inscribed radius R (R: four times the mean of
   the distance transform over the solid, exact for a ball), for the transform only: the labels keep the
   scan's pores as background;
2. the transform, smoothed over a voxel, is cut by a marker watershed at every maximum (h of half a voxel);
3. two neighbouring regions are one grain when the highest pass between them is at least MERGE_RATIO of
   the lower of their two peaks: across a contact between grains the transform drops to the contact's
   radius, far below either grain's, while across a dent it hardly drops. Merged from the highest pass
   down, as the watershed's own tree;
4. segments under *minVoxels* are dropped, not grains.

Measured on synthetic porous scans with the truth known (:func:`yade_mss.specimens.porousScan`;
``bench/segmentation.py``): the median best-overlap Jaccard index 0.90-0.93 for grains of 12 to 28 voxels'
semi-axis and 10-15 % intra-grain porosity, 0.73 at 20 % porosity or for grains of 7 to 12 voxels.
"""

import numpy as np

from ..base import integer, number, optional
from . import _options

SPECK_VOXELS = 27  # a solid piece smaller than a 3 x 3 x 3 cube is noise, not a grain
CLOSE_FRACTION = 0.15  # open pores closed by a ball of this fraction of the typical inscribed radius
MERGE_RATIO = 0.85  # neighbours whose highest pass reaches this fraction of the lower peak are one grain
SEGMENT_BYTES = 128  # bytes a voxel at the segmentation's peak: the transform, markers, watershed and copies


def _checkMemory(shape, memoryLimit):
    limit = number('segment', 'memoryLimit', _options.default('memoryLimit', 'generate') if memoryLimit is None
                   else memoryLimit, 0.0)
    need = float(np.prod(shape, dtype=float)) * SEGMENT_BYTES / 2 ** 30
    if need > limit:
        raise ValueError('segment: segmenting a scan of %s voxels needs about %.3g GiB (%d bytes a voxel, the whole '
                         'scan at once), over the memory limit of %.3g GiB (--memory-limit): crop the scan, or '
                         'label it with a tool of your own and give the labels' % (
                             'x'.join(str(n) for n in shape), need, SEGMENT_BYTES, limit))


def _passes(labels, dist):
    """{(a, b): the highest pass between neighbouring regions a < b}: over the faces between their voxels, the
    lower of the transform's two values, at its highest."""
    keys, values = [], []
    top = int(labels.max()) + 1
    for axis in range(3):
        a, b = [slice(None)] * 3, [slice(None)] * 3
        a[axis], b[axis] = slice(0, -1), slice(1, None)
        la, lb = labels[tuple(a)], labels[tuple(b)]
        m = (la != lb) & (la != 0) & (lb != 0)
        lo, hi = np.minimum(la[m], lb[m]).astype(np.int64), np.maximum(la[m], lb[m]).astype(np.int64)
        keys.append(lo * top + hi)
        values.append(np.minimum(dist[tuple(a)][m], dist[tuple(b)][m]))
    keys, values = np.concatenate(keys), np.concatenate(values)
    if not keys.size:
        return {}
    order = np.argsort(keys, kind='stable')
    keys, values = keys[order], values[order]
    starts = np.flatnonzero(np.r_[True, keys[1:] != keys[:-1]])
    highest = np.maximum.reduceat(values, starts)
    return {(int(k // top), int(k % top)): float(v) for k, v in zip(keys[starts], highest)}


def _merged(labels, dist, ratio):
    """The regions of *labels* joined where the pass between two reaches *ratio* of the lower peak: (labels,
    how many joins)."""
    from scipy import ndimage
    n = int(labels.max())
    peak = np.zeros(n + 1)
    if n:
        peak[1:] = ndimage.maximum(dist, labels, np.arange(1, n + 1))
    parent = np.arange(n + 1)

    def root(i):
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i
    joins = 0
    for (a, b), s in sorted(_passes(labels, dist).items(), key=lambda kv: -kv[1]):
        ra, rb = root(a), root(b)
        if ra != rb and s >= ratio * min(peak[ra], peak[rb]):
            parent[max(ra, rb)] = min(ra, rb)
            peak[min(ra, rb)] = max(peak[ra], peak[rb])
            joins += 1
    return np.array([root(i) for i in range(n + 1)], dtype=np.int32)[labels], joins


def segmentScan(binary, h=None, markers=None, minVoxels=0, memoryLimit=None):
    """A binary scan cut into grains (the module's pipeline), and what was done: ``(labels, info)``.

    :param binary: a 3-D array, non-zero where the solid is
    :param float h: the markers' least height, voxels: given, every maximum of the transform that stands this
        much above its saddles is a grain (the usual h-maxima pipeline, no merging); default: chosen from the
        grains' own size (the module's step 3)
    :param markers: a label volume of the user's own markers (non-zero voxels: seeds, one label a grain), the
        scan's shape: the watershed grows these, nothing is chosen here
    :param int minVoxels: segments under this are dropped (noise, not grains)
    :param memoryLimit: GiB, as generate's option (default its default): a scan whose segmentation would need
        more (about SEGMENT_BYTES a voxel, the whole scan at once) is refused before anything is allocated
    :return: (int32 labels 1..n, 0 the background; a dict: grains, h, inscribedRadius (R), closeRadius,
        mergeRatio, markers (the maxima, or the user's), merged (joins), specks and speckVoxels (dropped),
        poreVoxels (filled for the transform), small and smallVoxels (segments under minVoxels, dropped),
        method (a line saying how))
    """
    from scipy import ndimage
    from skimage.morphology import ball, h_maxima
    from skimage.segmentation import watershed
    h = optional(number, 'segment', 'segmentH', h, 0.0)
    minVoxels = integer('segment', 'minVoxels', minVoxels, 0)
    shape = np.shape(binary)
    if len(shape) != 3:
        raise ValueError('segment: the scan must be 3-D, got %d-D' % len(shape))
    _checkMemory(shape, memoryLimit)
    if markers is not None:
        markers = np.asarray(markers)
        if markers.shape != shape or not (markers.dtype == bool or np.issubdtype(markers.dtype, np.integer)):
            raise ValueError('segment: markers must be an integer volume of the scan\'s shape %s, got %s of %s'
                             % (shape, markers.shape, markers.dtype))
        if markers.dtype != bool and markers.min() < 0:
            raise ValueError('segment: markers must be labels >= 0 (0: no marker), found %d' % markers.min())
        markers = markers.astype(np.int64) if markers.dtype == bool else markers
    solid = np.asarray(binary) != 0
    pieces, n = ndimage.label(solid)
    sizes = np.bincount(pieces.ravel())
    speck = sizes < SPECK_VOXELS
    speck[0] = False
    info = dict(specks=int(speck.sum()), speckVoxels=int(sizes[speck].sum()))
    solid &= ~speck[pieces]
    del pieces
    body = ndimage.binary_fill_holes(solid)
    info['poreVoxels'] = int(np.count_nonzero(body & ~solid))
    R = 4.0 * float(ndimage.distance_transform_edt(body)[body].mean()) if body.any() else 0.0
    rc = int(round(CLOSE_FRACTION * R)) if h is None and markers is None else 0
    if rc > 0:  # the open pores too, for the transform
        p = rc + 1
        closed = ndimage.binary_closing(np.pad(body, p), ball(rc))[p:-p, p:-p, p:-p]
        body = ndimage.binary_fill_holes(closed | body)
        info['poreVoxels'] = int(np.count_nonzero(body & ~solid))
    dist = ndimage.gaussian_filter(ndimage.distance_transform_edt(body), 1.0)
    info.update(inscribedRadius=R, closeRadius=rc, h=h, mergeRatio=None, merged=0)
    if markers is not None:
        seeds, _ = ndimage.label(markers != 0) if markers.max() <= 1 else (np.where(body, markers, 0), None)
        info['markers'] = int(np.unique(seeds[seeds != 0]).size)
        info['method'] = 'the user\'s %d markers grown by a marker watershed' % info['markers']
    else:
        seeds, info['markers'] = ndimage.label(h_maxima(dist, 0.5 if h is None else h) & body)
    labels = watershed(-dist, seeds, mask=body).astype(np.int32)
    if markers is None and h is None:
        labels, info['merged'] = _merged(labels, dist, MERGE_RATIO)
        info['mergeRatio'] = MERGE_RATIO
        info['method'] = ('typical inscribed radius R %.3g voxels (4 x the mean distance transform); pores filled, '
                          'open ones closed by a ball of %d voxels (%.2f R); %d maxima of the transform, %d pairs '
                          'joined where the pass between them reaches %.2f of the lower peak'
                          % (R, rc, CLOSE_FRACTION, info['markers'], info['merged'], MERGE_RATIO))
    elif markers is None:
        info['method'] = '%d maxima of the transform at least h = %g voxels above their saddles' % (
            info['markers'], h)
    labels[~solid] = 0  # the scan's pores are not the grain's
    # a piece with no marker of its own (thinner than h) is a grain of its own; then segments under minVoxels go
    rest, m = ndimage.label(solid & (labels == 0))
    top = int(labels.max())
    labels[rest != 0] = rest[rest != 0] + top
    counts = np.bincount(labels.ravel())
    small = counts < max(minVoxels, 1)
    small[0] = False
    info.update(small=int(np.count_nonzero(small[counts > 0])), smallVoxels=int(counts[small].sum()))
    keep = (counts >= max(minVoxels, 1))
    keep[0] = False
    table = np.zeros(counts.size, np.int32)
    table[keep] = np.arange(1, int(keep.sum()) + 1, dtype=np.int32)
    labels = table[labels]
    info['grains'] = int(keep.sum())
    return labels, info


def segmentBinary(binary, h=None, memoryLimit=None, markers=None, minVoxels=0):
    """:func:`segmentScan`'s labels alone."""
    return segmentScan(binary, h, markers, minVoxels, memoryLimit)[0]
