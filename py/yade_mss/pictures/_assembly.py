"""An assembly of spheres seen from the side (:func:`sideView`): every sphere a disc at its place, the nearest
drawn last, a colour a grain. For the examples' pictures of specimens (no 3-D library: discs seen along an axis
are exact for spheres)."""

import numpy as np

from ..base import choice
from ._preview import pyplot, save


def sideView(centers, radii, groups, path, title='', axis='y', extra=None):
    """Draws spheres seen along *axis* (from its negative side) into the PNG *path*: a disc each, coloured by its
    group (a clump id, a grain label), the nearest in front.

    :param centers: (n, 3) sphere centres
    :param radii: n radii
    :param groups: n group keys (a colour each)
    :param path: the PNG to write
    :param title: the picture's title
    :param axis: 'x', 'y' or 'z', the direction of view
    :param extra: a function drawing more on a second panel: extra(ax), or None (one panel)
    """
    from matplotlib.collections import PatchCollection
    from matplotlib.patches import Circle
    plt = pyplot()
    a = 'xyz'.index(choice('sideView', 'axis', axis, ('x', 'y', 'z')))
    right, up = [k for k in range(3) if k != a]
    c, r = np.asarray(centers, dtype=float).reshape(-1, 3), np.asarray(radii, dtype=float).ravel()
    keys = sorted(set(groups), key=str)
    rng = np.random.default_rng(0)
    palette = {k: rng.uniform(0.2, 0.9, 3) for k in keys}
    order = np.argsort(c[:, a])[::-1]  # the farthest first, the nearest drawn over it
    fig, axs = plt.subplots(1, 2 if extra else 1, figsize=(12 if extra else 6.5, 6), dpi=110, squeeze=False)
    ax = axs[0][0]
    discs = [Circle((c[i, right], c[i, up]), r[i]) for i in order]
    shade = 0.75 + 0.25 * (c[order, a] - c[:, a].min()) / max(np.ptp(c[:, a]), 1e-300)  # nearer, brighter
    colours = [np.clip(palette[groups[i]] * s, 0, 1) for i, s in zip(order, shade)]
    ax.add_collection(PatchCollection(discs, facecolors=colours, edgecolors='k', linewidths=0.2))
    lo, hi = (c - r[:, None]).min(axis=0), (c + r[:, None]).max(axis=0)
    ax.set_xlim(lo[right], hi[right])
    ax.set_ylim(lo[up], hi[up])
    ax.set_aspect('equal')
    ax.set_xlabel('%s (m)' % 'xyz'[right])
    ax.set_ylabel('%s (m)' % 'xyz'[up])
    ax.set_title('%d spheres, %d grains, seen along %s' % (len(r), len(keys), 'xyz'[a]))
    if extra:
        extra(axs[0][1])
    fig.suptitle(title)
    fig.tight_layout()
    save(fig, path, plt, title=title)
