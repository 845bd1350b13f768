"""Draws docs/femur70.png, the README's picture: the femur mesh and 70 spheres three ways: unbounded (radii grow
past the mesh wherever that lowers the mismatch), the default (no sphere more than one voxel beyond the mesh), and
clipped (none beyond), with D (eq. 27) on an independent grid and the largest protrusion in voxels.
The figures it shows are written into the PNG's text too (its Description), so that ``--check`` (run by
scripts/docs.sh, in CI) computes them again with this build and fails where the stored picture is stale.
usage: PYTHONPATH=build/py /usr/bin/python3 docs/make_figure.py [--check]   (build first; python3-matplotlib)"""
import os
import sys

import matplotlib
matplotlib.use('Agg')
import matplotlib.pyplot as plt
import numpy as np

import yade_mss

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
FEMUR = os.path.join(ROOT, 'tests', 'data', 'human_femur.stl')


def mesh_triangles(path):
    """Vertices (n, 3, 3) of the triangles of a mesh file (our own reader)."""
    v, t = yade_mss._mss.readMesh(path)[:2]
    return np.asarray(v, float).reshape(-1, 3)[np.asarray(t, int).reshape(-1, 3)]


def spheres(ax, r, color):
    u, v = np.mgrid[0:2 * np.pi:16j, 0:np.pi:10j]
    for c, rad in zip(r.centers, r.radii):
        ax.plot_surface(c[0] + rad * np.cos(u) * np.sin(v), c[1] + rad * np.sin(u) * np.sin(v),
                        c[2] + rad * np.cos(v), color=color, linewidth=0, shade=True)


def bumps(r):
    """The largest protrusion beyond the mesh, in voxels of the generation grid."""
    return r.metrics['protrusion'] / r.grid['voxelSize']


OUT = os.path.join(ROOT, 'docs', 'femur70.png')


def clumps():
    """The three clumps and the panels' titles (what the picture says, figures rounded as shown)."""
    tris = mesh_triangles(FEMUR)
    free = yade_mss.generate(FEMUR, nSpheres=70, resolution=103, maxProtrusion=float('inf'))
    bounded = yade_mss.generate(FEMUR, nSpheres=70, resolution=103)
    clipped = yade_mss.generate(FEMUR, nSpheres=70, resolution=103, clip=True)
    panels = [('femur mesh (X-ray CT), %d triangles' % len(tris), None),
              ('unbounded: D = %.4f, bumps up to %.1f voxels' % (yade_mss.score(FEMUR, free)['dice'], bumps(free)),
               free),
              ('default: D = %.4f, at most %.1f voxel out' % (yade_mss.score(FEMUR, bounded)['dice'], bumps(bounded)),
               bounded),
              ('clipped: D = %.4f, none out' % yade_mss.score(FEMUR, clipped)['dice'], clipped)]
    return tris, panels


def check():
    """Fails (exit 1) where docs/femur70.png says other figures than this build computes."""
    from PIL import Image
    stored = Image.open(OUT).text.get('Description', '')
    now = ' | '.join(title for title, _ in clumps()[1])
    if stored != now:
        sys.exit('docs/femur70.png is stale: it shows\n  %s\nthis build computes\n  %s\nrun PYTHONPATH=build/py '
                 '/usr/bin/python3 docs/make_figure.py' % (stored or '(no figures recorded)', now))
    print('docs/femur70.png: its figures are this build\'s (%s)' % now)


def main():
    tris, panels = clumps()
    free, bounded, clipped = (r for _, r in panels[1:])
    fig = plt.figure(figsize=(15, 5.2))
    lo, hi = tris.reshape(-1, 3).min(0), tris.reshape(-1, 3).max(0)
    colors = {id(free): '#4f7cac', id(bounded): '#b0704f', id(clipped): '#6a9f58'}
    for i, (title, r) in enumerate(panels):
        ax = fig.add_subplot(1, 4, i + 1, projection='3d')
        if r is None:
            ax.plot_trisurf(tris[:, :, 0].ravel(), tris[:, :, 1].ravel(), tris[:, :, 2].ravel(),
                            triangles=np.arange(3 * len(tris)).reshape(-1, 3), color='#c8b89a', linewidth=0)
        else:
            spheres(ax, r, colors[id(r)])
        for set_lim, a, b in zip((ax.set_xlim, ax.set_ylim, ax.set_zlim), lo, hi):
            set_lim(a, b)
        ax.set_box_aspect(tuple(hi - lo), zoom=1.0)
        ax.view_init(elev=12, azim=-60)
        ax.set_axis_off()
        ax.set_title(title, fontsize=10)
    fig.subplots_adjust(left=0, right=1, bottom=0, top=0.93, wspace=0)
    fig.savefig(OUT, dpi=90, metadata={'Description': ' | '.join(title for title, _ in panels)})
    print('wrote', OUT)


if __name__ == '__main__':
    check() if sys.argv[1:] == ['--check'] else main()
