"""Draws a mesh written by mss surface, shaded (the manual's picture of the femur's clump surface).
usage: /usr/bin/python3 docs/draw_surface.py MESH.ply OUT.png"""
import sys

import matplotlib
matplotlib.use('Agg')
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402

from yade_mss import _mss  # noqa: E402


def main(mesh, out):
    v, t = _mss.readMesh(mesh)
    v, t = np.reshape(v, (-1, 3)), np.reshape(t, (-1, 3))
    tri = v[t]
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    light = np.array([0.4, -0.5, 0.75])
    light /= np.linalg.norm(light)
    shade = 0.25 + 0.75 * np.clip(n @ light, 0, 1)
    fig = plt.figure(figsize=(6, 6), dpi=120)
    ax = fig.add_subplot(projection='3d')
    ax.add_collection3d(Poly3DCollection(tri, facecolors=plt.cm.copper(shade), edgecolors='none'))
    lo, hi = v.min(axis=0), v.max(axis=0)
    c, h = (lo + hi) / 2, (hi - lo).max() / 2
    ax.set_xlim(c[0] - h, c[0] + h)
    ax.set_ylim(c[1] - h, c[1] + h)
    ax.set_zlim(c[2] - h, c[2] + h)
    ax.set_box_aspect((1, 1, 1))
    ax.view_init(elev=15, azim=-60)
    ax.set_axis_off()
    ax.set_title('mss surface: %d triangles, closed' % len(t))
    fig.savefig(out, bbox_inches='tight')


if __name__ == '__main__':
    main(*sys.argv[1:3])
