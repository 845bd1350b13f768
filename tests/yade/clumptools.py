"""Shared helpers of the YADE tests: independent sums (numpy only), plain clumps, tensors."""
import math
import os
import struct

import numpy as np

DATA = os.environ.get('MSS_TEST_DATA', os.path.join('tests', 'data'))
ELL = os.path.join(DATA, 'ellipsoid_2_1_1.stl')
FEMUR = os.path.join(DATA, 'human_femur.stl')


def rot(q):
    m = q.toRotationMatrix()
    return np.array([[m[i, j] for j in range(3)] for i in range(3)])


def tensor(state):
    R = rot(state.ori)
    return R.dot(np.diag([state.inertia[0], state.inertia[1], state.inertia[2]])).dot(R.T)


def vec(v):
    return np.array([v[0], v[1], v[2]])


def readStlTriangles(path):
    """Triangles (n, 3, 3) of an ASCII or binary STL, read here with numpy alone."""
    with open(path, 'rb') as f:
        raw = f.read()
    if raw[:5] == b'solid' and b'facet' in raw[:1000]:
        v = [list(map(float, l.split()[1:4])) for l in raw.decode('ascii', 'replace').splitlines()
             if l.strip().startswith('vertex')]
        return np.array(v).reshape(-1, 3, 3)
    n = struct.unpack('<I', raw[80:84])[0]
    a = np.frombuffer(raw[84:84 + 50 * n], dtype=np.dtype([('n', '<f4', 3), ('v', '<f4', (3, 3)), ('a', '<u2')]))
    return a['v'].astype(float)


def meshMass(tri):
    """Volume, centroid, inertia tensor about the centroid (unit density) of a closed triangle mesh: signed
    tetrahedra from the origin (divergence theorem), an implementation independent of the C++ one."""
    a, b, c = tri[:, 0], tri[:, 1], tri[:, 2]
    v = np.einsum('ij,ij->i', a, np.cross(b, c)) / 6.0
    V = v.sum()
    cen = (v[:, None] * (a + b + c) / 4.0).sum(axis=0) / V
    # second moments of each tetrahedron (0, a, b, c): integral x x^T = v/20 (sum p p^T + (sum p)(sum p)^T)
    s = a + b + c
    S = (np.einsum('i,ij,ik->jk', v, a, a) + np.einsum('i,ij,ik->jk', v, b, b) + np.einsum('i,ij,ik->jk', v, c, c)
         + np.einsum('i,ij,ik->jk', v, s, s)) / 20.0
    S -= V * np.outer(cen, cen)
    return V, cen, np.trace(S) * np.eye(3) - S


def unionByGrid(centers, radii, h):
    """Volume, centroid and inertia tensor (unit density) of a union of spheres, by numpy on a grid of step h:
    independent of the C++ code."""
    lo = (centers - radii[:, None]).min(axis=0)
    hi = (centers + radii[:, None]).max(axis=0)
    xs, ys, zs = [np.arange(lo[a] + h / 2, hi[a], h) for a in range(3)]
    Y, Z = np.meshgrid(ys, zs, indexing='ij')
    n = 0
    s1 = np.zeros(3)
    s2 = np.zeros((3, 3))
    for x in xs:
        inside = np.zeros(Y.shape, dtype=bool)
        for c, r in zip(centers, radii):
            inside |= (x - c[0]) ** 2 + (Y - c[1]) ** 2 + (Z - c[2]) ** 2 <= r * r
        y, z = Y[inside], Z[inside]
        p = np.stack([np.full(y.shape, x), y, z], axis=1)
        n += len(p)
        s1 += p.sum(axis=0)
        s2 += p.T.dot(p)
    V = n * h ** 3
    c = s1 / n
    cov = s2 / n - np.outer(c, c) + np.eye(3) * h * h / 12.0
    I = V * (np.trace(cov) * np.eye(3) - cov)
    return V, c, I


def ballSums(centers, radii, density):
    """What YADE's discretization-0 sum gives for spheres: solid balls, overlaps counted twice."""
    m = density * 4.0 / 3.0 * math.pi * radii ** 3
    M = m.sum()
    C = (m[:, None] * centers).sum(axis=0) / M
    I = np.zeros((3, 3))
    for mi, ri, xi in zip(m, radii, centers):
        d = xi - C
        I += 0.4 * mi * ri * ri * np.eye(3) + mi * (d.dot(d) * np.eye(3) - np.outer(d, d))
    return M, C, I


def relErr(a, b):
    return float(np.linalg.norm(np.asarray(a) - np.asarray(b)) / np.linalg.norm(np.asarray(b)))


def halfSpaceMass(tri, point, normal):
    """Volume, centroid and inertia tensor (unit density) of the part of a closed mesh (triangles (n, 3, 3)) on
    the side of the plane its normal points to: each triangle clipped with numpy, the cut closed by a fan from
    the plane's point. Written apart from the C++ split, so that the pieces are checked independently."""
    n = np.asarray(normal, dtype=float) / np.linalg.norm(normal)
    p0 = np.asarray(point, dtype=float)
    kept, segs = [], []
    for t in tri:
        s = (t - p0).dot(n)
        poly, entry, exit_ = [], None, None
        for q in range(3):
            a, b, sa, sb = t[q], t[(q + 1) % 3], s[q], s[(q + 1) % 3]
            if sa >= 0:
                poly.append(a)
            if (sa >= 0) != (sb >= 0):
                x = a + (b - a) * (sa / (sa - sb))
                poly.append(x)
                if sa >= 0:
                    exit_ = x
                else:
                    entry = x
        for q in range(1, len(poly) - 1):
            kept.append((poly[0], poly[q], poly[q + 1]))
        if entry is not None:
            segs.append((entry, exit_))
    kept += [(p0, e, x) for e, x in segs]
    return meshMass(np.array(kept))
