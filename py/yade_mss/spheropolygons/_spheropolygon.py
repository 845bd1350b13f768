"""Spheropolygons from 2-D particle images (the second paper: Dobrohotoff et al., Granular Matter 2012):
:func:`spheropolygon` (Algorithm 1, in C++) and :func:`ochart` (the choice of N and r, eq. 5-8, Fig. 4).

Convention, as for volumes: array element [i, j] has its centre at (x, y) = origin + pixelSize (i, j).
"""

import csv
import math
import os
import time

import numpy as np

from .. import _mss
from ..base import (atomicWrite, checkWork, choice, flag, integer, number, numberList, optional, readNpy,
                    requireRegularFile, vector)
from ..grains import optionTable

_DEFAULT_RADII = (0.0025, 0.004, 0.006, 0.01, 0.02)  # fractions of the particle's size


def readImage(path, threshold=None):
    """A 2-D image from a .npy array (non-zero: particle; integer labels kept) or a PNG (dark = particle:
    grey below *threshold*, default 0.5). PNG rows run down the picture; here j runs up (element [i, j])."""
    path = os.fspath(path)
    ext = os.path.splitext(path)[1].lower()
    requireRegularFile('readImage', path)
    if ext == '.npy':
        if threshold is not None:  # said, not ignored: a .npy image is particles (non-zero) and background
            raise ValueError('%s: threshold applies to a PNG\'s grey levels; a .npy image is already particles '
                             '(non-zero) and background (0): give it without threshold' % path)
        a = readNpy('readImage', path)
        if a.ndim != 2:
            raise ValueError('%s: the image must be 2-D, got %d-D' % (path, a.ndim))
        if not (a.dtype == bool or np.issubdtype(a.dtype, np.integer)):
            raise ValueError('%s: dtype %s is not boolean or integer (threshold it first)' % (path, a.dtype))
        return a
    if ext == '.png':
        import matplotlib
        matplotlib.use('Agg')
        import matplotlib.image as mpimg
        _checkPngSize(path)
        try:
            img = mpimg.imread(path)
        except Exception as e:  # a decoder of hostile bytes (PIL raises OSError, SyntaxError, struct.error, ...)
            raise ValueError('%s: cannot read the PNG (%s)' % (path, e)) from None
        grey = img[..., :3].mean(axis=-1) if img.ndim == 3 else img
        t = 0.5 if threshold is None else float(threshold)
        return (grey < t)[::-1].T  # [row, col] from the top -> [i, j] with j up
    raise ValueError("%s: unknown image extension '%s' (expected .npy or .png)" % (path, ext))


MAX_IMAGE_PIXELS = 1 << 28  # a 16384 x 16384 image; a PNG may declare 4e9 x 4e9 in its first 24 bytes


def _checkPngSize(path):
    """Refuses a PNG whose header declares more than MAX_IMAGE_PIXELS, before the decoder allocates them."""
    try:
        with open(path, 'rb') as f:
            head = f.read(24)
    except OSError as e:
        raise ValueError('%s: cannot read the PNG (%s)' % (path, e)) from None
    if len(head) < 24 or head[:8] != b'\x89PNG\r\n\x1a\n' or head[12:16] != b'IHDR':
        raise ValueError('%s: not a PNG file (no PNG signature and header)' % path)
    width, height = int.from_bytes(head[16:20], 'big'), int.from_bytes(head[20:24], 'big')
    if width * height > MAX_IMAGE_PIXELS:
        raise ValueError('%s: the PNG declares %d x %d pixels (at most %d)' % (path, width, height, MAX_IMAGE_PIXELS))


def _fit(mask, vertices, radius, pixelSize, origin, init='auto', **options):
    """One fit; init 'auto' runs the boundary and the curvature initialisations and keeps the better (on our
    cow the boundary start ends at 2.3% and the curvature start at 5%, where the paper found curvature best)."""
    if init == 'auto':
        fits = [_fit(mask, vertices, radius, pixelSize, origin, i, **options) for i in ('boundary', 'curvature')]
        return min(fits, key=lambda x: x['errorPixels'])
    m = np.asarray(mask) != 0
    data = np.ascontiguousarray(m.T.astype(np.uint8)).tobytes()  # x fastest: element [i, j] at i + nx j
    opts = dict(options, vertices=int(vertices), radius=float(radius), init=init)
    r = _mss.spheropolygon(data, m.shape[0], m.shape[1], float(pixelSize), [float(x) for x in origin], opts)
    r['init'] = init
    return r


def _checkFitWork(mask, vertices, fits, starts, maxWork):
    """Refuses *fits* fits of *starts* starts each whose estimate exceeds *maxWork* seconds. Measured on a 2-core
    machine with the defaults (six fits of two starts): a particle of 420^2 pixels 16.5 s at 30 vertices, 67 s
    at 100; of 840^2 over 100 s at 30: about 0.62 ns a pixel of the particle's box, times the box's edge and the
    vertices, a start."""
    idx = np.argwhere(mask)
    box = np.ptp(idx, axis=0) + 1
    pixels = float(np.prod(box))
    seconds = 0.62e-9 * pixels * math.sqrt(pixels) * vertices * fits * starts
    checkWork('spheropolygon', '%d fits of %d vertices to a particle of %d x %d pixels' % (fits * starts, vertices,
                                                                                        box[0], box[1]),
                seconds, maxWork, 'ask for fewer vertices, give the spheroradius, or a coarser image')


MAX_VERTICES = 10000  # the fit is O(N^2) a sweep: beyond this no particle image has the pixels to place them


def spheropolygon(image, vertices=30, radius=None, pixelSize=1.0, origin=(0.0, 0.0), label=None, init='auto',
                  inset=True, radii=None, vertexRadii=False, minRadius=None, regionVertices=False,
                  regionTurning=None, maxWork=None, **options):
    """The spheropolygon of N vertices that best matches a particle image (Algorithm 1).

    :param image: 2-D array (non-zero: the particle) or a .npy/.png file
    :param int vertices: N
    :param float radius: the spheroradius r (world units); None: the one of least error among *radii*
    :param float pixelSize: a pixel's edge, world units
    :param origin: the world position of the centre of pixel [0, 0], 2 numbers
    :param label: of a labelled image, the particle to describe
    :param radii: the spheroradii tried without *radius*, fractions of the particle's size (default 0.0025 to
        0.02)
    :param float minRadius: with vertexRadii: no radius below this (world units; default the spheroradius)
    :param float regionTurning: with regionVertices: the turning (degrees) that makes a region (default 90)
    :param str init: 'circle', 'boundary' or 'curvature' (section 3.1), or 'auto' (default): boundary and
        curvature both, the better kept
    :param bool inset: start the vertices one spheroradius inside the boundary (beyond the paper)
    :param bool vertexRadii: a spheroradius per vertex (3N parameters; the paper's section 5), tuned after the
        equal-radius fit; none below *minRadius* (world units; default the spheroradius, so that the contact
        stiffness and time step, set by the smallest radius, are never worse than with one radius)
    :param bool regionVertices: at least one vertex in every convex or concave region of the boundary that
        turns by at least *regionTurning* degrees (the paper's section 4), put at the region's centre where
        the fit left none and kept there (default 90 degrees)
    :param float maxWork: seconds: refuse a fit whose estimated work is more, before it starts (default 600; the
        estimate counts the image's particle box and the vertices)
    :param options: samplingRadius (r_s, world units), samples (n_s), weight (g), cutoff, tolerance,
        maxIterations, relocations (default 10; 0: the paper's Algorithm 1 alone)
    :return: dict with spheroradius (with vertexRadii the smallest), vertices [[x, y], ...], radii (with
        vertexRadii), errorPixels, error (fraction of the particle's pixels), iterations, roundness (eq. 9),
        area, perimeter, history, seconds; with regionVertices also regions, regionsFilled (vertices put in)
        and regionsMissed (regions left without a vertex: more regions than vertices)
    """
    F = 'spheropolygon'
    vertices = integer(F, 'vertices', vertices, 3, MAX_VERTICES)  # 10**6 ran for hours
    radius = optional(number, F, 'radius', radius, 0.0)
    pixelSize = _pixelSize(F, pixelSize)
    origin = vector(F, 'origin', origin, 2).tolist()
    label = optional(integer, F, 'label', label)
    init = choice(F, 'init', init, ('auto', 'circle', 'boundary', 'curvature'))
    inset, vertexRadii = flag(F, 'inset', inset), flag(F, 'vertexRadii', vertexRadii)
    regionVertices = flag(F, 'regionVertices', regionVertices)
    radii = optional(numberList, F, 'radii', radii, 0.0)
    minRadius = optional(number, F, 'minRadius', minRadius, 0.0)
    regionTurning = optional(number, F, 'regionTurning', regionTurning, 0.0, 360.0)
    a = readImage(image) if isinstance(image, (str, os.PathLike)) else np.asarray(image)
    if a.ndim != 2 or a.size == 0:
        raise ValueError('spheropolygon: the image must be 2-D and not empty')
    mask = (a == label) if label is not None else (a != 0)
    if not mask.any():
        raise ValueError('spheropolygon: no particle pixel%s' % ('' if label is None else ' with label %s' % label))
    if label is None and a.dtype != bool and len(np.unique(a[a != 0])) > 1:
        raise ValueError('spheropolygon: the image holds several labels: choose one (label=), or use '
                         'spheropolygons() for all')
    if regionTurning is not None and not regionVertices:
        raise ValueError('spheropolygon: regionTurning sets what counts as a region: it needs regionVertices=True')
    if minRadius is not None and not vertexRadii:
        raise ValueError('spheropolygon: minRadius bounds the radii per vertex: it needs vertexRadii=True')
    maxWork = optionTable.check('spheropolygon', 'spheropolygon', 'maxWork',
                             optionTable.default('maxWork', 'spheropolygon') if maxWork is None else maxWork)
    _checkFitWork(mask, vertices, 1 if radius is not None else len(radii or _DEFAULT_RADII) + 1,
                  2 if init == 'auto' else 1, maxWork)
    t0 = time.perf_counter()
    relocations = options.pop('relocations', 10)
    final = dict(options, vertexRadii=bool(vertexRadii), regionVertices=bool(regionVertices),
                 regionTurning=90.0 if regionTurning is None else float(regionTurning))
    if minRadius is not None:
        final['minRadius'] = float(minRadius)
    if radius is None:  # the spheroradius of least error, found without relocations, then refined with them
        idx = np.argwhere(mask)
        size = pixelSize * (np.ptp(idx, axis=0).max() + 1)
        lowest = 0.0 if minRadius is None else float(minRadius)  # no spheroradius under the bound
        candidates = sorted({max(f * size, lowest) for f in (radii or _DEFAULT_RADII)})
        fits = [_fit(mask, vertices, c, pixelSize, origin, init=init, inset=inset, **options) for c in candidates]
        best = min(fits, key=lambda x: (x['errorPixels'], -x['spheroradius']))
        radius, init = best['spheroradius'], best['init']
    r = _fit(mask, vertices, radius, pixelSize, origin, init=init, inset=inset, relocations=relocations, **final)
    r['vertices'] = [list(v) for v in r['vertices']]
    r['seconds'] = time.perf_counter() - t0
    return r


def _list(func, name, value):
    if isinstance(value, (str, bytes, dict)) or not hasattr(value, '__iter__'):
        raise TypeError('%s: %s must be a list, got %r' % (func, name, value))
    return list(value)


def _pixelSize(func, value):
    v = number(func, 'pixelSize', value)
    if not v > 0:
        raise ValueError('%s: pixelSize must be > 0, got %r' % (func, value))
    return v


def boundaryRegions(image, minTurning=90.0, pixelSize=1.0, origin=(0.0, 0.0), label=None):
    """The convex and concave regions of a particle's boundary (as regionVertices uses them): a list of dicts
    with first, last, coreFirst, coreLast (the stretch where the middle half of the turning is done: a vertex
    whose nearest boundary point lies there is in the region), centre (indices into the smoothed boundary),
    turning (degrees; > 0 convex), and that smoothed boundary as an (n, 2) array.

    :param image: 2-D array (non-zero: the particle) or a .npy/.png file
    :param float minTurning: the least turning of a region, degrees
    :param float pixelSize: a pixel's edge, world units
    :param origin: the world position of the centre of pixel [0, 0], 2 numbers
    :param label: of a labelled image, the particle
    :return: (list of region dicts, (n, 2) array)
    """
    F = 'boundaryRegions'
    minTurning = number(F, 'minTurning', minTurning, 0.0, 360.0)
    pixelSize = _pixelSize(F, pixelSize)
    origin = vector(F, 'origin', origin, 2).tolist()
    label = optional(integer, F, 'label', label)
    a = readImage(image) if isinstance(image, (str, os.PathLike)) else np.asarray(image)
    m = (a == label) if label is not None else (a != 0)
    data = np.ascontiguousarray(m.T.astype(np.uint8)).tobytes()
    regions, boundary = _mss.spheropolygonRegions(data, m.shape[0], m.shape[1], pixelSize, origin, minTurning)
    return ([dict(first=f, last=l, coreFirst=cf, coreLast=cl, centre=c, turning=t)
             for f, l, cf, cl, c, t in regions],
            np.array(boundary, float).reshape(-1, 2))


def spheropolygons(image, **kw):
    """One spheropolygon per label of a labelled image.

    :param image: a labelled 2-D array (0: background) or a .npy file
    :param kw: :func:`spheropolygon`'s keywords
    :return: {label: result}
    """
    a = readImage(image) if isinstance(image, (str, os.PathLike)) else np.asarray(image)
    return {int(l): spheropolygon(a, label=l, **kw) for l in np.unique(a[a != 0])}


def ochart(image, outdir, vertices=(4, 6, 10, 15, 20, 30), radii=(0.005, 0.01, 0.02, 0.05, 0.1),
           pixelSize=1.0, origin=(0.0, 0.0), label=None, **options):
    """Choosing N and r (section 3.2): the error for each (N, r), the normalised cost T ~ N / sqrt(r) (eq. 7)
    and O = T x error (eq. 8), written as ``ochart.csv`` and three contour charts (``ochart.png``: Fig. 4) in
    *outdir*, the global and the best non-trivial minimum of O marked. *radii* are fractions of the particle's
    size (the paper's normalised r).

    :param image: 2-D array (non-zero: the particle) or a .npy/.png file
    :param outdir: the folder to write into
    :param vertices: the vertex counts N swept
    :param radii: the spheroradii swept, fractions of the particle's size
    :param float pixelSize: a pixel's edge, world units
    :param origin: the world position of the centre of pixel [0, 0], 2 numbers
    :param label: of a labelled image, the particle
    :param options: :func:`spheropolygon`'s keywords
    :return: the rows
    """
    F = 'ochart'
    vertices = [integer(F, 'vertices', n, 3, MAX_VERTICES) for n in _list(F, 'vertices', vertices)]
    radii = numberList(F, 'radii', radii, 0.0)
    if len(set(vertices)) < 2 or len(set(radii)) < 2:  # a contour chart needs a plane of them
        raise ValueError('ochart: the chart is drawn over vertex counts and radii: give at least 2 distinct of '
                         'each, got vertices %s and radii %s' % (vertices, radii))
    pixelSize = _pixelSize(F, pixelSize)
    origin = vector(F, 'origin', origin, 2).tolist()
    label = optional(integer, F, 'label', label)
    a = readImage(image) if isinstance(image, (str, os.PathLike)) else np.asarray(image)
    mask = (a == label) if label is not None else (a != 0)
    idx = np.argwhere(mask)
    if not len(idx):
        raise ValueError('ochart: no particle pixel')
    size = pixelSize * (np.ptp(idx, axis=0).max() + 1)
    rows = []
    for n in vertices:
        for f in radii:
            t0 = time.perf_counter()
            r = _fit(mask, n, f * size, pixelSize, origin, **options)
            rows.append({'N': n, 'r': f, 'radius': f * size, 'error': 100 * r['error'],
                         'errorPixels': r['errorPixels'], 'T': n / math.sqrt(f), 'roundness': r['roundness'],
                         'seconds': time.perf_counter() - t0})
    tmax = max(x['T'] for x in rows)
    for x in rows:
        x['T'] /= tmax
        x['O'] = x['T'] * x['error']
    os.makedirs(outdir, exist_ok=True)
    def table(tmp):
        with open(tmp, 'w', newline='') as f:
            w = csv.DictWriter(f, fieldnames=list(rows[0]))
            w.writeheader()
            w.writerows(rows)
    atomicWrite(os.path.join(outdir, 'ochart.csv'), table, 'ochart')
    _ochartFigure(rows, vertices, radii, os.path.join(outdir, 'ochart.png'))
    return rows


def _ochartFigure(rows, vertices, radii, path):
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    N, R = np.meshgrid(np.array(vertices, float), np.array(radii, float), indexing='ij')
    grid = {k: np.array([[next(x[k] for x in rows if x['N'] == n and x['r'] == r) for r in radii] for n in vertices])
            for k in ('error', 'T', 'O')}
    o = grid['O']
    g = np.unravel_index(np.argmin(o), o.shape)
    # the best non-trivial minimum: the least O among the (N, r) whose error is at most twice the least error
    ok = grid['error'] <= 2 * grid['error'].min()
    nt = np.unravel_index(np.argmin(np.where(ok, o, np.inf)), o.shape)
    fig, axs = plt.subplots(1, 3, figsize=(15, 4.6), dpi=100)
    for ax, (k, title) in zip(axs, (('error', 'error (% of the particle\'s pixels)'),
                                    ('T', 'cost T ~ N / sqrt(r) (eq. 7), normalised'), ('O', 'O = T x error (eq. 8)'))):
        cs = ax.contourf(N, R, grid[k], levels=14, cmap='viridis')
        ax.contour(N, R, grid[k], levels=14, colors='k', linewidths=0.3)
        fig.colorbar(cs, ax=ax)
        ax.plot(N[g], R[g], 'r*', ms=14, label='global minimum of O')
        ax.plot(N[nt], R[nt], 'wo', ms=9, mec='k', label='best with error <= 2x the least')
        ax.set_xlabel('vertices N')
        ax.set_ylabel('spheroradius r / particle size')
        ax.set_title(title)
    axs[2].legend(fontsize=8, loc='upper right')
    fig.suptitle('O-chart (Dobrohotoff et al. 2012, Fig. 4): global minimum of O at N = %d, r = %.3g; best '
                 'non-trivial at N = %d, r = %.3g' % (N[g], R[g], N[nt], R[nt]))
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def previewSpheropolygon(mask, result, path, pixelSize=1.0, origin=(0.0, 0.0)):
    """The spheropolygon over the image: the particle grey, error pixels red (missed) and blue (extra)."""
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    from matplotlib.patches import Circle, Polygon
    m = np.asarray(mask) != 0
    v = np.array(result['vertices'])
    r = result.get('radii') or [result['spheroradius']] * len(v)
    sp = rasterizeNumpy(v, r, m.shape, pixelSize, origin)
    img = np.ones(m.shape + (3,))
    img[m & sp] = (0.75, 0.75, 0.72)
    img[m & ~sp] = (0.85, 0.2, 0.15)
    img[~m & sp] = (0.15, 0.35, 0.85)
    fig, ax = plt.subplots(figsize=(9, 9 * m.shape[1] / m.shape[0] + 0.8), dpi=100)
    ext = (origin[0] - pixelSize / 2, origin[0] + pixelSize * (m.shape[0] - 0.5),
           origin[1] - pixelSize / 2, origin[1] + pixelSize * (m.shape[1] - 0.5))
    ax.imshow(np.transpose(img, (1, 0, 2))[::-1], extent=ext, interpolation='nearest')
    ax.add_patch(Polygon(v, closed=True, fill=False, ec='k', lw=1))
    for p, rp in zip(v, r):
        ax.add_patch(Circle(p, rp, fill=False, ec='k', lw=0.4, alpha=0.6))
    ax.plot(v[:, 0], v[:, 1], 'k.', ms=4)
    ax.set_aspect('equal')
    rtext = 'r = %.3g' % r[0] if 'radii' not in result else 'r = %.3g to %.3g' % (min(r), max(r))
    ax.set_title('N = %d, %s: error %.2f%% (%d pixels), roundness %.3f\nred: particle missed, blue: '
                 'outside the particle' % (len(v), rtext, 100 * result['error'], result['errorPixels'],
                                           result['roundness']))
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def rasterizeNumpy(vertices, radius, shape, pixelSize=1.0, origin=(0.0, 0.0)):
    """f(SP) computed here in numpy alone (matplotlib's point-in-polygon and segment distances): an
    independent check of the C++ image of a spheropolygon. *radius*: one, or one per vertex (an edge is then
    the hull of its two vertex discs: the least of |p - c(t)| - r(t) over t found by golden-section search,
    not by the C++ closed form)."""
    from matplotlib.path import Path
    v = np.asarray(vertices, float)
    rv = np.broadcast_to(np.asarray(radius, float), (len(v),))
    i, j = np.meshgrid(np.arange(shape[0]), np.arange(shape[1]), indexing='ij')
    P = np.stack([origin[0] + pixelSize * i, origin[1] + pixelSize * j], axis=-1).reshape(-1, 2)
    inside = Path(v).contains_points(P) if len(v) >= 3 else np.zeros(len(P), bool)
    near = np.zeros(len(P), bool)
    for a, b, ra, rb in zip(v, np.roll(v, -1, axis=0), rv, np.roll(rv, -1)):
        ab = b - a
        if ra == rb:
            t = np.clip(((P - a) @ ab) / max(ab @ ab, 1e-300), 0, 1)
            near |= ((a + t[:, None] * ab - P) ** 2).sum(axis=1) <= ra * ra
            continue
        f = lambda t: np.hypot(*(a + t[:, None] * ab - P).T) - (ra + t * (rb - ra))
        lo, hi, g = np.zeros(len(P)), np.ones(len(P)), (math.sqrt(5) - 1) / 2
        for _ in range(60):  # f is convex in t
            x1, x2 = hi - g * (hi - lo), lo + g * (hi - lo)
            left = f(x1) < f(x2)
            hi, lo = np.where(left, x2, hi), np.where(left, lo, x1)
        near |= np.minimum(np.minimum(f(lo), f(hi)), np.minimum(f(np.zeros(len(P))), f(np.ones(len(P))))) <= 0
    return (inside | near).reshape(shape)


def cow(width=420, height=300):
    """A cow-like silhouette (body, head, four legs, a thin tail), as in the paper's Fig. 1: array [i, j]."""
    x, y = np.meshgrid(np.arange(width), np.arange(height), indexing='ij')
    body = ((x - 210) / 120.0) ** 2 + ((y - 170) / 60.0) ** 2 <= 1
    head = ((x - 345) / 38.0) ** 2 + ((y - 205) / 30.0) ** 2 <= 1
    neck = (x > 300) & (x < 340) & (y > 165) & (y < 215)
    legs = np.zeros_like(body)
    for x0 in (120, 155, 255, 290):
        legs |= (x >= x0) & (x < x0 + 18) & (y >= 35) & (y < 130)
    tail = (np.abs(y - (175 - 0.9 * (95 - x))) < 2.5) & (x > 40) & (x < 95)
    horn = ((x - 360) / 6.0) ** 2 + ((y - 240) / 12.0) ** 2 <= 1
    return body | head | neck | legs | tail | horn
