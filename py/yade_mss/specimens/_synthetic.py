"""Synthetic specimens for tests, benchmarks and tutorials: labelled volumes made as real pipelines make them
(a Voronoi ball, packed balls cut by a marker watershed, separated balls)."""

import math
import warnings

import numpy as np

from ..base import INT64_MAX, flag, integer, number, randomRotation
from ..grains import separated

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
    lines = flag('voronoiBall', 'lines', lines)
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
    lines = flag(func, 'lines', lines)
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
    :param int maxTries: placements tried before giving up on more grains (it gives up sooner, with a warning,
        after PATIENCE tries in a row fail: the volume is full)
    :return: int32 array, labels 1..n (n may fall short of *grains* if they do not fit: then a warning says so)
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
    placed, missed = 0, 0
    for _ in range(maxTries):
        if placed == grains or missed >= PATIENCE:
            break
        missed += 1
        R = randomRotation(rng)
        parts = [(np.zeros(3), rng.uniform(lo, hi, 3))]
        for _ in range(rng.integers(1, 3)):
            parts.append((R.dot(rng.normal(0, 0.6 * lo, 3)), rng.uniform(0.6 * lo, 0.9 * hi, 3)))
        reach = int(math.ceil(max(np.linalg.norm(c) + a.max() for c, a in parts))) + gap
        centre = rng.uniform(0, np.array(shape))  # grains near a face are cut by it
        box = [slice(max(0, int(centre[d]) - reach), min(shape[d], int(centre[d]) + reach + 1)) for d in range(3)]
        if any(s.stop - s.start < 2 for s in box):
            continue
        if grown[tuple(min(shape[d] - 1, int(centre[d])) for d in range(3))]:
            continue  # its centre is in a grain's reach: it cannot fit (the test below, at a glance)
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
        missed = 0
        labels[tuple(box)][inside] = placed
        grown[tuple(box)] |= near
    if placed < grains:
        warnings.warn('syntheticSpecimen: %d of %d grains placed: the rest do not fit (%s in a %s volume, %d '
                      'voxels apart; %d tries in a row failed): a larger shape, fewer or smaller grains, or a '
                      'smaller gap' % (placed, grains, 'semi-axes %g to %g' % (lo, hi), 'x'.join(map(str, shape)),
                                       gap, missed), stacklevel=2)
    return labels


PATIENCE = 300  # placements failing in a row before syntheticSpecimen gives up (the volume is as full as it gets)


def porousScan(shape=(100, 100, 100), grains=40, size=(7, 12), porosity=0.1, specks=300, noise=0.35, seed=1):
    """A thresholded micro-CT of porous grains, and its true separation: what a binary scan of carbonate sand
    looks like, for tests and benchmarks of segmentation. Grains are randomly oriented ellipsoids (axes in
    ratio 1 : 0.6-1 : 0.5-1) packed so that neighbours touch (each centre placed at most a few voxels from the
    grains already there, overlaps given to the nearer surface); inside each, pores (balls of 1 to 2.5 voxels)
    up to *porosity* of its volume, some open to its surface; in the space between, *specks* (blobs of 1 to
    10 voxels); then the scan's grey levels (solid 1, void 0) with Gaussian noise of *noise* smoothed over a
    voxel, thresholded at 1/2 (rough surfaces, lone voxels, pinholes), as real scans are.

    :param shape: the volume's size, 3 integers (voxels)
    :param int grains: how many grains to place (fewer where they do not fit)
    :param size: the range of the grains' largest semi-axis, voxels
    :param float porosity: the intra-grain pores' share of a grain's volume, in [0, 0.3]
    :param int specks: noise blobs in the void
    :param float noise: the grey levels' noise (standard deviation, the solid's level being 1), in [0, 0.5]
    :param int seed: random seed
    :return: (the scan, uint8 0/1; the truth, int32 labels 1..n of each grain's solid voxels, its pores 0)
    """
    from scipy import ndimage
    func = 'porousScan'
    if isinstance(shape, (str, bytes)) or not hasattr(shape, '__len__') or len(shape) != 3:
        raise TypeError('%s: shape must be 3 integers, got %r' % (func, shape))
    shape = tuple(integer(func, 'shape', n, 16, 1024) for n in shape)
    grains = integer(func, 'grains', grains, 1, 100000)
    if isinstance(size, (str, bytes)) or not hasattr(size, '__len__') or len(size) != 2:
        raise TypeError('%s: size must be (smallest, largest) semi-axis in voxels, got %r' % (func, size))
    lo, hi = (number(func, 'size', v, 3.0, 200.0) for v in size)
    if lo > hi:
        raise ValueError('%s: size must be (smallest, largest), got %r' % (func, size))
    porosity = number(func, 'porosity', porosity, 0.0, 0.3)
    specks = integer(func, 'specks', specks, 0, 10 ** 7)
    noise = number(func, 'noise', noise, 0.0, 0.5)
    rng = np.random.default_rng(integer(func, 'seed', seed, 0, INT64_MAX))
    n = np.array(shape)
    best = np.full(shape, np.inf)  # each voxel's least normalised distance to a grain (< 1: inside it)
    truth = np.zeros(shape, np.int32)
    centres, radii, shapes, placed = [], [], [], 0
    for _ in range(50 * grains):
        if placed == grains:
            break
        a = rng.uniform(lo, hi)
        axes = a * np.array([1.0, rng.uniform(0.6, 1.0), rng.uniform(0.5, 1.0)])
        R = randomRotation(rng)
        if centres:  # beside a grain already placed, their surfaces touching (a contact flattened by 0-10 %)
            k = rng.integers(len(centres))
            d = rng.normal(size=3)
            d /= np.linalg.norm(d)
            reach = lambda Rk, ak, u: 1.0 / np.sqrt(((u @ Rk) ** 2 / ak ** 2).sum())  # noqa: E731
            c = centres[k] + d * (reach(*shapes[k], d) + reach(R, axes, -d)) * rng.uniform(0.9, 1.0)
        else:
            c = n / 2.0
        if np.any(c < 0) or np.any(c >= n):
            continue
        if centres and np.min(np.linalg.norm(np.array(centres) - c, axis=1) / (np.array(radii) + axes[2])) < 0.8:
            continue  # too deep in another: it would be a sliver
        box = tuple(slice(max(0, int(c[d] - a - 1)), min(shape[d], int(c[d] + a + 2))) for d in range(3))
        grid = np.stack(np.meshgrid(*[np.arange(s.start, s.stop) for s in box], indexing='ij'), axis=-1) - c
        f = np.sqrt(((grid @ R) ** 2 / axes ** 2).sum(axis=-1))
        placed += 1
        mine = f < np.minimum(1.0, best[box])
        best[box] = np.where(mine, f, best[box])
        truth[box] = np.where(mine, placed, truth[box])
        centres.append(c)
        radii.append(a)
        shapes.append((R, axes))
    if placed < grains:
        warnings.warn('%s: placed %d of %d grains' % (func, placed, grains))
    # pores: balls carved inside each grain up to its share (a ball that reaches the surface is an open pore)
    sizes = np.bincount(truth.ravel(), minlength=placed + 1)
    for g in range(1, placed + 1):
        idx = np.argwhere(truth == g)
        carved, target = 0, porosity * sizes[g]
        while carved < target and len(idx):
            c, r = idx[rng.integers(len(idx))], rng.uniform(1.0, 2.5)
            box = tuple(slice(max(0, int(c[d] - r)), min(shape[d], int(c[d] + r) + 1)) for d in range(3))
            grid = np.stack(np.meshgrid(*[np.arange(s.start, s.stop) for s in box], indexing='ij'), axis=-1) - c
            ball = ((grid ** 2).sum(axis=-1) <= r * r) & (truth[box] == g)
            carved += int(ball.sum())
            truth[box][ball] = 0
    grey = (truth != 0).astype(float)
    void = np.argwhere(truth == 0)
    for c in void[rng.integers(len(void), size=specks)] if len(void) and specks else []:
        r = rng.uniform(0.5, 1.4)
        box = tuple(slice(max(0, int(c[d] - r)), min(shape[d], int(c[d] + r) + 1)) for d in range(3))
        grid = np.stack(np.meshgrid(*[np.arange(s.start, s.stop) for s in box], indexing='ij'), axis=-1) - c
        grey[box][(grid ** 2).sum(axis=-1) <= r * r] = 1.0
    if noise > 0:
        grey = ndimage.gaussian_filter(grey + rng.normal(0.0, noise, shape), 0.7)
    scan = (grey > 0.5).astype(np.uint8)
    present = np.unique(truth[truth != 0])
    table = np.zeros(placed + 1, np.int32)
    table[present] = np.arange(1, present.size + 1, dtype=np.int32)
    return scan, table[truth]


def bestOverlap(labels, truth):
    """Each true grain's best-overlap Jaccard index against a segmentation: |T & S| / |T | S| for the segment S
    that shares most voxels with the grain T (0 where none does). A list in the truth's label order."""
    labels, truth = np.asarray(labels), np.asarray(truth)
    t = truth.ravel().astype(np.int64)
    s = labels.ravel().astype(np.int64)
    both = (t != 0) & (s != 0)
    pairs, counts = np.unique(np.column_stack([t[both], s[both]]), axis=0, return_counts=True)
    tsize = np.bincount(t, minlength=int(t.max()) + 1)
    ssize = np.bincount(s, minlength=int(s.max()) + 1)
    out = np.zeros(int(t.max()) + 1)
    for (a, b), k in zip(pairs, counts):
        out[a] = max(out[a], k / (tsize[a] + ssize[b] - k))
    return out[1:][tsize[1:] > 0].tolist()
