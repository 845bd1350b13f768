"""The member loads that make YADE's clump sums exact, in plain numpy (no YADE needed, tested alone).

YADE 2023.02a's ``Clump::updateProperties`` (what ``appendClumped``, ``updateClumpProperties`` and friends call)
at discretization 0 sums its members with the parallel-axis theorem: a ``Sphere`` member as a solid ball of its
material's density (so overlapping spheres are counted twice), any other member with its own ``state.mass``,
``state.inertia`` and ``state.ori`` (the tensor ``R diag(inertia) R^T`` with ``R`` the matrix of
``ori.conjugate()``). Given the wanted mass M, centre of mass C and inertia tensor I (about C, world axes), this
module chooses per member a mass m_i and, for one member, a tensor J such that those sums give exactly M, C, I:

    sum m_i = M,   sum m_i (x_i - C) = 0,   J + sum m_i T(x_i - C) = I,   T(d) = |d|^2 1 - d d^T.

The masses are positive where possible (then they are also the members' final masses: each sphere carries its
share of the clump's mass, and the members' masses add up to the clump's); J is whatever remains.
"""

import numpy as np


def parallelAxis(d):
    """T(d) = |d|^2 1 - d d^T: the inertia of a unit point mass at offset d."""
    d = np.asarray(d, dtype=float)
    return d.dot(d) * np.eye(3) - np.outer(d, d)


def _logsumexp(z):
    m = z.max()
    return m + np.log(np.exp(z - m).sum())


def tiltedShares(centers, weights, M, C):
    """Positive masses m_i at *centers*, summing to *M* with centre of mass *C*, as close to proportional to
    *weights* as possible (least relative entropy): m_i ~ w_i exp(lambda . (x_i - C)), lambda by Newton's method
    on the convex log-sum-exp, whose gradient is the weighted mean offset. Such masses exist exactly when C lies
    inside the convex hull of the centres; O(n) per iteration, a few iterations.

    :return: (m, ok), ok False when C is outside the hull (m is then the best found, not exact)
    """
    d = np.asarray(centers, dtype=float) - C
    L = max(float(np.abs(d).max()), 1e-300)
    dn = d / L
    logw = np.log(np.asarray(weights, dtype=float))
    lam = np.zeros(3)

    def f(l):
        return _logsumexp(logw + dn.dot(l))

    g = np.zeros(3)
    f0 = f(lam)
    for _ in range(100):
        z = logw + dn.dot(lam)
        p = np.exp(z - z.max())
        p /= p.sum()
        g = p.dot(dn)
        if np.linalg.norm(g) < 1e-13:
            break
        H = (dn * p[:, None]).T.dot(dn) - np.outer(g, g)
        step = -np.linalg.lstsq(H, g, rcond=1e-12)[0]
        # Armijo, with the rounding of f allowed: near the optimum a Newton step changes f by less than its
        # rounding, and a strict test halved the step some 40 times an iteration (a split's piece spent
        # milliseconds here)
        slope = g.dot(step)
        t, slack = 1.0, 1e-14 * (1.0 + abs(f0))
        f1 = f(lam + step)
        while t > 1e-12 and f1 > f0 + 1e-4 * t * slope + slack:
            t *= 0.5
            f1 = f(lam + t * step)
        if t <= 1e-12:
            break
        lam, f0 = lam + t * step, f1
        # C on or beyond the hull's boundary: f has no minimum and lambda runs off; shares of exp(-100)
        # relative to their weights are no solution anyway
        if np.abs(lam).max() > 1e4:
            break
    m = M * p
    return m, bool(np.linalg.norm(g) < 1e-10)


def _polish(centers, m, M, C):
    """The least change of *m* that makes the sum M and the centre of mass C exact to rounding."""
    d = centers - C
    A = np.vstack([np.ones(len(m)), d.T])
    r = np.array([M, 0.0, 0.0, 0.0]) - A.dot(m)
    return m + np.linalg.lstsq(A, r, rcond=None)[0]


class Loads(object):
    """What :func:`memberLoads` returns.

    :ivar m: temporary member masses for YADE's sums (sum M, centre of mass ``centroid``)
    :ivar final: the members' masses afterwards (positive, sum M)
    :ivar j, V: the tensor J for member 0: eigenvalues and eigenvectors (columns; a rotation)
    :ivar centroid: the centre of mass the masses give: C, unless C is off the affine hull of the centres
    :ivar offset: distance from C to that centre (0 when exact)
    """


def memberLoads(centers, radii, M, C, I):
    """Member masses and one member's tensor making YADE's clump sums equal *M*, *C*, *I* (see the module)."""
    x = np.asarray(centers, dtype=float).reshape(-1, 3)
    r = np.asarray(radii, dtype=float).reshape(-1)
    C = np.asarray(C, dtype=float).reshape(3)
    I = np.asarray(I, dtype=float).reshape(3, 3)
    if not (M > 0 and np.isfinite(M)):
        raise ValueError('memberLoads: mass must be > 0 and finite, got %r' % (M,))
    base = r ** 3  # proportional to the balls' own masses
    out = Loads()
    # C off the affine hull of the centres (one sphere, collinear or coplanar ones) cannot be reached by masses
    # at the centres: the nearest point of the hull is taken, and the distance reported
    mean = x.mean(axis=0)
    size = max(float(np.ptp(x, axis=0).max() + 2 * r.max()), 1e-300)
    U, sv, _ = np.linalg.svd((x - mean).T, full_matrices=False)
    U = U[:, sv > 1e-12 * size]
    reach = mean + U.dot(U.T.dot(C - mean))
    out.offset = float(np.linalg.norm(reach - C))
    if out.offset <= 1e-9 * size:
        reach, out.offset = C, 0.0
    out.centroid = reach
    m, positive = tiltedShares(x, base, M, reach) if len(r) > 1 else (np.array([float(M)]), True)
    out.m = _polish(x, m, M, reach)
    out.final = out.m if (positive and np.all(out.m > 0)) else M * base / base.sum()
    d = x - out.centroid
    J = I - (out.m.dot((d * d).sum(axis=1)) * np.eye(3) - (out.m[:, None] * d).T.dot(d))  # sum m_i T(d_i)
    J = 0.5 * (J + J.T)
    out.j, out.V = np.linalg.eigh(J)
    if np.linalg.det(out.V) < 0:
        out.V[:, 2] = -out.V[:, 2]
    return out


def sumsAsYade(centers, radii, masses, tensors, density=None):
    """Mass, centre and tensor (about the centre) that YADE's sums give for point members with *masses* and own
    *tensors* (3x3 each) at *centers*; with *density*, spheres as solid balls instead. For tests."""
    x = np.asarray(centers, dtype=float).reshape(-1, 3)
    if density is not None:
        r = np.asarray(radii, dtype=float)
        masses = density * 4.0 / 3.0 * np.pi * r ** 3
        tensors = [0.4 * mi * ri * ri * np.eye(3) for mi, ri in zip(masses, r)]
    M = float(np.sum(masses))
    C = (np.asarray(masses)[:, None] * x).sum(axis=0) / M
    I = sum(t + mi * parallelAxis(xi - C) for mi, t, xi in zip(masses, tensors, x))
    return M, C, I
