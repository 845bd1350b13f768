"""A clump against its grain (:func:`preview`, ``mss preview``): three views and a section.

Rendering is done here in numpy, orthographically, and written with matplotlib's Agg backend (Debian's
python3-matplotlib; no display, no OpenGL context): a sphere seen along an axis is exactly a disc whose depth is
known in closed form, and the grain is seen as the depth of its first solid voxel on a fine grid. That needs no
3-D library, is exact for the spheres, and draws 200 spheres in well under a second per view.
"""

import math
import os

import numpy as np

from .. import _mss
from ..base import atomicWrite, checkWork, progressBar
from ..grains import VOLUME_EXT, Mesh, MssResult, compareMany, optionTable, readGrain, readSpheres

_AXES = {'x': (1, 2, 0), 'y': (0, 2, 1), 'z': (0, 1, 2)}  # (right, up, towards the viewer)


def pyplot():
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    return plt


def grainVoxels(grain, resolution=160, voxelSize=None, origin=None, label=None, scale=None):
    """The grain as voxels (bool array (nx, ny, nz)), voxel size and origin: a mesh voxelised with
    *resolution* voxels along its shortest edge, a volume as it is."""
    s = readGrain(grain, voxelSize, origin, label, scale)
    if isinstance(s, Mesh):
        data, dims, h, org = _mss.voxelizeMesh(*s.args(), int(resolution))
    else:
        data, dims, h, org = s.data, s.shape, s.voxelSize, s.origin
    a = np.frombuffer(data, dtype=np.uint8).reshape(dims, order='F') != 0
    return a, float(h), np.asarray(org, dtype=float)


def _view(solid, h, origin, centers, radii, colors, axis, pixel, showGrain=True):
    """One orthographic view along *axis* from its positive side: an RGB image and its extent."""
    right, up, depth = _AXES[axis]
    lo = np.minimum(origin - h / 2, (centers - radii[:, None]).min(axis=0))
    hi = np.maximum(origin + h * (np.array(solid.shape) - 0.5), (centers + radii[:, None]).max(axis=0))
    W, H = int(math.ceil((hi[right] - lo[right]) / pixel)), int(math.ceil((hi[up] - lo[up]) / pixel))
    u = lo[right] + (np.arange(W) + 0.5) * pixel
    v = lo[up] + (np.arange(H) + 0.5) * pixel
    # the grain: depth of its first solid voxel seen from +depth, on its own grid, sampled at the pixels
    seen = solid.transpose(right, up, depth)
    anyv = seen.any(axis=2)
    first = np.where(anyv, seen.shape[2] - 1 - np.argmax(seen[:, :, ::-1], axis=2), -1)
    gz = origin[depth] + h * first
    iu = np.clip(np.round((u - origin[right]) / h).astype(int), 0, seen.shape[0] - 1)
    iv = np.clip(np.round((v - origin[up]) / h).astype(int), 0, seen.shape[1] - 1)
    inside_u = (u >= origin[right] - h / 2) & (u <= origin[right] + h * (seen.shape[0] - 0.5))
    inside_v = (v >= origin[up] - h / 2) & (v <= origin[up] + h * (seen.shape[1] - 0.5))
    grain = anyv[np.ix_(iu, iv)] & inside_u[:, None] & inside_v[None, :] & showGrain
    gdepth = np.where(grain, gz[np.ix_(iu, iv)] + h / 2, -np.inf)
    # the spheres: depth z = c + sqrt(r^2 - rho^2), the nearest wins
    sdepth = np.full((W, H), -np.inf)
    shade = np.zeros((W, H))
    index = np.full((W, H), -1)
    for q in np.argsort(centers[:, depth]):
        c, r = centers[q], radii[q]
        i0, i1 = max(0, int((c[right] - r - lo[right]) / pixel)), min(W, int((c[right] + r - lo[right]) / pixel) + 2)
        j0, j1 = max(0, int((c[up] - r - lo[up]) / pixel)), min(H, int((c[up] + r - lo[up]) / pixel) + 2)
        du = u[i0:i1, None] - c[right]
        dv = v[None, j0:j1] - c[up]
        rho2 = du * du + dv * dv
        inside = rho2 <= r * r
        z = np.where(inside, c[depth] + np.sqrt(np.maximum(r * r - rho2, 0)), -np.inf)
        win = z > sdepth[i0:i1, j0:j1]
        sdepth[i0:i1, j0:j1] = np.where(win, z, sdepth[i0:i1, j0:j1])
        shade[i0:i1, j0:j1] = np.where(win, np.sqrt(np.maximum(1 - rho2 / (r * r), 0)), shade[i0:i1, j0:j1])
        index[i0:i1, j0:j1] = np.where(win, q, index[i0:i1, j0:j1])
    # light the grain by its depth's slope, the spheres by their normal (Lambert, light from the viewer)
    gshade = np.zeros((W, H))
    if grain.any():
        gd = np.where(grain, gdepth, np.nanmin(np.where(grain, gdepth, np.nan)))
        k = max(1, int(round(1.5 * h / pixel)))  # smooth the voxel steps over about three voxels
        for axis_ in (0, 1):
            gd = sum(np.roll(gd, s_, axis=axis_) for s_ in range(-k, k + 1)) / (2 * k + 1)
        gy, gx = np.gradient(gd, pixel)
        gshade = 1 / np.sqrt(1 + gx * gx + gy * gy)
    img = np.ones((W, H, 3))
    # a sphere shows where it stands out of the grain by more than half a voxel (closer, the two coincide
    # within the voxelisation and would flicker)
    front = (sdepth >= gdepth + 0.5 * h) & (index >= 0)
    img[grain] = (0.55 + 0.4 * gshade[grain])[:, None] * np.array([0.85, 0.85, 0.82])
    img[front] = (0.35 + 0.65 * shade[front])[:, None] * colors[index[front]]
    # the grain's silhouette over everything, so that where the spheres miss or overshoot it shows
    edge = grain ^ np.roll(grain, 1, axis=0) | grain ^ np.roll(grain, 1, axis=1)
    img[edge] = (0.1, 0.1, 0.1)
    return np.transpose(img, (1, 0, 2))[::-1], (lo[right], hi[right], lo[up], hi[up])


def _section(solid, h, origin, centers, radii, axis):
    """A section through the grain's centroid normal to *axis*: grain only (missed), spheres only (bump), both."""
    right, up, depth = _AXES[axis]
    idx = np.argwhere(solid)
    k = int(round(idx[:, depth].mean()))
    sl = np.take(solid, k, axis=depth)
    if right > up:
        sl = sl.T
    zc = origin[depth] + h * k
    u = origin[right] + h * np.arange(sl.shape[0])
    v = origin[up] + h * np.arange(sl.shape[1])
    U, V = np.meshgrid(u, v, indexing='ij')
    covered = np.zeros(sl.shape, dtype=bool)
    for c, r in zip(centers, radii):
        d2 = r * r - (zc - c[depth]) ** 2
        if d2 > 0:
            covered |= (U - c[right]) ** 2 + (V - c[up]) ** 2 <= d2
    img = np.ones(sl.shape + (3,))
    img[sl & covered] = (0.78, 0.78, 0.75)
    img[sl & ~covered] = (0.85, 0.2, 0.15)  # the grain, missed
    img[~sl & covered] = (0.15, 0.35, 0.85)  # the spheres, outside the grain
    ext = (u[0] - h / 2, u[-1] + h / 2, v[0] - h / 2, v[-1] + h / 2)
    return np.transpose(img, (1, 0, 2))[::-1], ext, zc


def drawingSeconds(radii, pixel):
    """The drawing's estimated seconds: each view a numpy pass a sphere over its box of pixels, the section a
    pass a sphere. Measured on a 2-core machine (the ellipsoid, 3,000 to 30,000 spheres of 10 to 150 pixels
    across): 28 us a sphere and view plus 17.5 ns a pixel of its box, 20 us a sphere for the section; taken
    as 50 us, 20 ns and 40 us, the high side."""
    box = (2.0 * np.asarray(radii, dtype=float) / pixel + 2.0) ** 2
    return 4 * (50e-6 * len(box) + 20e-9 * float(np.sum(box))) + 40e-6 * len(box)


def preview(grain, spheres, path, resolution=160, title=None, voxelSize=None, origin=None, label=None,
            scoreResolution=100, maxWork=None, scale=None):
    """Draws a clump against its grain: three orthographic views (spheres coloured by how far they protrude,
    the grain's silhouette over them) and a section through the centroid (red: grain the spheres miss; blue:
    spheres outside the grain), with n, D (independent grid) and the largest protrusion in the caption.

    :param grain: mesh file, voxel file, array, (vertices, triangles)
    :param spheres: an :class:`MssResult` or a sphere file
    :param path: the PNG to write (2000 px wide)
    :return: the comparison row (see :func:`compareMany`)
    """
    plt = pyplot()
    from matplotlib import cm, colors as mcolors
    sp = spheres if isinstance(spheres, MssResult) else readSpheres(spheres)
    if len(sp) == 0:
        raise ValueError('preview: no spheres')
    maxWork = optionTable.check('preview', 'preview', 'maxWork', optionTable.default('maxWork', 'preview')
                             if maxWork is None else maxWork)
    solid, h, org = grainVoxels(grain, resolution, voxelSize, origin, label, scale)
    if not solid.any():
        raise ValueError('preview: the grain has no solid voxel')
    size = float(np.max(np.array(solid.shape) * h))
    drawing = drawingSeconds(sp.radii, size / 400.0)
    checkWork('preview', 'drawing %d spheres in five panels' % len(sp), drawing, maxWork, 'draw fewer spheres')
    row = compareMany(grain, [sp], resolution=scoreResolution, voxelSize=voxelSize, origin=origin, label=label,
                      align='none', maxWork=maxWork, scale=scale)[0]
    protr = np.asarray(row['sphereProtrusion'])
    vmax = max(protr.max(), 0.02 * size)
    norm = mcolors.Normalize(vmin=0, vmax=vmax)
    import matplotlib
    cmap = matplotlib.colormaps['viridis']
    colors = cmap(norm(protr))[:, :3]
    pixel = size / 400.0
    fig, axs = plt.subplots(1, 5, figsize=(20, 5.2), dpi=100, constrained_layout=True)
    panels = (('y', False, 'the clump alone, along -y'), ('y', True, 'with the grain, along -y'),
              ('x', True, 'with the grain, along -x'), ('z', True, 'with the grain, along -z'))
    bar = progressBar(5, 'mss preview', drawing)
    for ax, (axis, withGrain, label_) in zip(axs[:4], panels):
        img, ext = _view(solid, h, org, sp.centers, sp.radii, colors, axis, pixel, withGrain)
        bar.update()
        ax.imshow(img, extent=ext, interpolation='nearest')
        r, u, _ = _AXES[axis]
        ax.set_xlabel('xyz'[r])
        ax.set_ylabel('xyz'[u])
        ax.set_title(label_)
    img, ext, zc = _section(solid, h, org, sp.centers, sp.radii, 'z')
    bar.update()
    bar.close()
    axs[4].imshow(img, extent=ext, interpolation='nearest')
    axs[4].set_title('section z = %.4g (red: missed, blue: outside)' % zc, fontsize=10)
    axs[4].set_xlabel('x')
    axs[4].set_ylabel('y')
    sm = cm.ScalarMappable(norm=norm, cmap=cmap)
    fig.colorbar(sm, ax=axs[3], fraction=0.05, pad=0.02, label='sphere protrusion (world units)')
    name = title or (getattr(sp, 'source', '') or 'spheres')
    voxels = isinstance(grain, np.ndarray) or (isinstance(grain, (str, os.PathLike)) and os.path.splitext(
        os.fspath(grain))[1].lower() in VOLUME_EXT)  # scored on its own voxels: the generation grid's D
    grid = 'on the volume\'s own voxels' if voxels else 'independent grid of %d voxels' % scoreResolution
    fig.suptitle('%s: n = %d spheres, D = %.4f (eq. 27, %s), largest protrusion %.3g (%.2f%% of the grain\'s '
                 'size)' % (name, len(sp), row['dice'], grid, row['protrusion'], 100 * row['protrusion'] / size))
    fig.supxlabel('views: the grain grey (its outline black), the spheres coloured by how far they protrude, '
                  'shown where they stand out of it by over half a voxel; section through the centroid: red = grain '
                  'the spheres miss, blue = spheres outside the grain, grey = both', fontsize=9)
    save(fig, path, plt, title=name)
    return row


def save(fig, path, plt, title=None):
    """Writes *fig* to the PNG *path* (atomically) and closes it; *title* also goes into the PNG's metadata
    (its Title text), where a program finds what the picture shows."""
    path = os.fspath(path)
    if not path.lower().endswith('.png'):
        plt.close(fig)
        raise ValueError('%s: pictures are written as .png' % path)
    try:
        atomicWrite(path, lambda tmp: fig.savefig(tmp, metadata={'Title': title} if title else None), 'picture')
    finally:
        plt.close(fig)
