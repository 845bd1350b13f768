"""Sets of clumps to and from files with their exact mass properties (next to YADE's own textClumps)."""

import os

import numpy as np

from .. import _mss
from ..base import atomicWrite, split
from ..exports import HEADER, parseClumps
from ._clumps import bodyOptions, buildClump, clumpIdList, stateTensor, yadeModules

def writeClumps(path, clumpIds=None):
    """Writes clumps of spheres to a text file: YADE's ``x y z r clumpId`` lines (what ``export.textClumps``
    writes, at full precision) and, per clump, a ``#mss clump`` line with its mass, centre of mass, inertia
    tensor (world axes) and density, as the clump has them now. Written atomically.

    :param path: the file to write
    :param clumpIds: the clumps to write (default: every clump in the scene)
    :return: (number of clumps, number of spheres)
    """
    utils, O, me = yadeModules()
    from yade.wrapper import Sphere
    ids = clumpIdList('writeClumps', clumpIds, O)
    lines = [HEADER]
    spheres = 0
    for cid in ids:
        body = O.bodies[cid] if 0 <= cid < len(O.bodies) else None
        if body is None or not body.isClump:
            raise ValueError('writeClumps: body %d is not a clump' % cid)
        members = [O.bodies[i] for i in sorted(body.shape.members.keys())]
        if not all(isinstance(b.shape, Sphere) for b in members):
            raise ValueError('writeClumps: clump %d has members that are not spheres' % cid)
        st = body.state
        I = stateTensor(st)
        lines.append('#mss clump %d density %r mass %r centroid %r %r %r inertia %r %r %r %r %r %r\n'
                     % ((cid, members[0].material.density, st.mass) + tuple(float(v) for v in st.pos)
                        + (I[0, 0], I[1, 1], I[2, 2], I[0, 1], I[0, 2], I[1, 2])))
        for b in members:
            lines.append('%r %r %r %r %d\n' % (b.state.pos[0], b.state.pos[1], b.state.pos[2], b.shape.radius, cid))
            spheres += 1
    def write(tmp):
        with open(tmp, 'w') as f:
            f.writelines(lines)
    atomicWrite(path, write, 'writeClumps')
    return len(ids), spheres


def readClumps(path, **body):
    """Reads a file of :func:`writeClumps` (or YADE's ``export.textClumps``) and appends its clumps, each with
    the mass properties written for it scaled to the density of the material used now (a file without them:
    those of the union of its spheres, overlaps counted once).

    :param path: the file to read
    :param body: keywords of ``utils.sphere`` (material, color, mask, fixed, ...)
    :return: list of (clumpId, [memberIds]) in the order of the file; nothing is added if the file is bad
    """
    body, = split('readClumps', body, bodyOptions(), extra=('path',))
    utils, O, me = yadeModules()
    path = os.fspath(path)
    groups, headers = parseClumps(path)
    out = []
    for cid, rows in groups.items():
        a = np.array(rows)
        if cid in headers:
            h = headers[cid]
            rho, M = h[0], h[1]
            if not (rho > 0 and M > 0):
                raise ValueError('readClumps: %s: clump %d: density and mass must be > 0' % (path, cid))
            xx, yy, zz, xy, xz, yz = h[5:]
            V, C = M / rho, np.array(h[2:5])
            I = np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]]) / rho
        else:
            u = _mss.massSpheres(a[:, :3].ravel().tolist(), a[:, 3].tolist(), 200)
            V, C, I = u['volume'], np.array(u['centroid']), np.reshape(u['inertia'], (3, 3))
        try:
            out.append(buildClump(a[:, :3], a[:, 3], V, C, I, body))
        except Exception:
            for c, m in out:
                O.bodies.erase(c, True)
            raise
    return out
