#!/usr/bin/python3
"""How low can D go for the regular tetrahedron at 30 spheres under the one-voxel bound?

An experiment outside the engine, to tell the optimiser's shortfall from the bound's. The tetrahedron inscribed in
[-1/2, 1/2]^3 (axis-aligned, generation resolution 103: one voxel h = 1/103) is a convex polytope, so a sphere
centred inside it at plane distance d = min_k (b_k - n_k . c) protrudes by exactly r - d, and the bound is r <= d + h.
The search space is exactly that: centres c_i and radii r_i = softmin(rho_i, d(c_i) + h) (so never past the bound).
The objective is the Dice mismatch (eq. 27) of a smooth union, u_i(p) = sigmoid((r_i - |p - c_i|) / (tau h)),
U = 1 - prod(1 - u_i), over a lattice of 1/64 near the grain, minimised by L-BFGS with tau lowered 2 -> 0.3 voxel;
the result is scored by Monte Carlo (exact geometry, seeded, its standard error printed), by our engine's
independent grid (mss compare, the bar's metric) and by its largest protrusion.

Starts: the engine's own output (polished), and random centres inside the grain. The same optimiser without the
bound (radii free) calibrates it against the engine's unbounded result.

Then the polished set shaken (basin hopping) and, for the sphere count the bar takes, the engine's output at other
counts polished.

usage: bench/tetra_bound.py [--starts K] [--shake K] [--counts N,N,...]   (defaults 6, 6, 33,35,37,38; the
unbounded search takes max(2, K / 3) random starts; a bounded start takes 1-2 minutes on one core, an unbounded
one 4-7: about 45 minutes in all)
"""
import argparse
import os
import sys
import tempfile
import time

import numpy as np
from scipy.optimize import minimize

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from fidelity import run, tetrahedron  # noqa: E402

VERTS = np.array([[.5, .5, .5], [.5, -.5, -.5], [-.5, .5, -.5], [-.5, -.5, .5]])
H = 1 / 103.
N_SPHERES = 30


def faces():
    """Outward unit normals n_k and offsets b_k: the grain is n_k . x <= b_k."""
    normals, offsets = [], []
    for k in range(4):
        a, b, c = (VERTS[j] for j in range(4) if j != k)
        n = np.cross(b - a, c - a)
        n /= np.linalg.norm(n)
        if n @ (VERTS[k] - a) > 0:
            n = -n
        normals.append(n)
        offsets.append(n @ a)
    return np.array(normals), np.array(offsets)


NORMALS, OFFSETS = faces()


def planeDistance(C):
    return (OFFSETS[None, :] - C @ NORMALS.T)


def softmin(values, beta):
    """-beta log sum exp(-v / beta) <= min(v) and its weights (the gradient with respect to each value)."""
    m = values.min(1, keepdims=True)
    w = np.exp(-(values - m) / beta)
    s = w.sum(1, keepdims=True)
    return m[:, 0] - beta * np.log(s[:, 0]), w / s


def radii(C, rho, bounded, beta=0.25 * H):
    """Radii and their gradients: d r / d c (n x 3) and d r / d rho (n)."""
    if not bounded:
        return rho, np.zeros_like(C), np.ones_like(rho)
    values = np.c_[planeDistance(C) + H, rho]
    r, w = softmin(values, beta)
    return r, -(w[:, :4] @ NORMALS), w[:, 4]


def lattice(bounded, spacing=1 / 64., margin=0.08):
    g = np.arange(-0.5 - margin + 0.0031, 0.5 + margin, spacing)
    P = np.stack([a.ravel() for a in np.meshgrid(g, g, g, indexing='ij')], 1)
    outside = (P @ NORMALS.T - OFFSETS).max(1)
    if bounded:  # nothing lies beyond h of the grain's planes
        keep = outside <= 1.5 * H
        P, outside = P[keep], outside[keep]
    return P, (outside <= 0).astype(float)


def objective(P, inA, bounded, n):
    """The smooth mismatch of n spheres over the points P (inA: in the grain) and its gradient."""
    A = inA.sum()

    def mismatch(x, tau):
        C, rho = x[:3 * n].reshape(n, 3), x[3 * n:]
        r, drdc, drdrho = radii(C, rho, bounded)
        diff = P[None, :, :] - C[:, None, :]
        dist = np.sqrt((diff ** 2).sum(2)) + 1e-12
        u = 1 / (1 + np.exp(-np.clip((r[:, None] - dist) / (tau * H), -40, 40)))
        u = np.minimum(u, 1 - 1e-9)
        empty = np.exp(np.log1p(-u).sum(0))
        U = 1 - empty
        inter, size = (U * inA).sum(), U.sum() + A
        D = 1 - 2 * inter / size
        # dD/dz_ip, z = (r_i - |p - c_i|) / (tau h)
        g = (-2 * (inA * size - inter) / size ** 2)[None, :] * empty[None, :] * u / (tau * H)
        gr = g.sum(1)
        gc = (g[:, :, None] * (diff / dist[:, :, None])).sum(1) + gr[:, None] * drdc
        return D, np.r_[gc.ravel(), gr * drdrho]
    return mismatch


def optimise(C, rho, bounded, iters=100, taus=(2., 1., .5, .3)):
    n = len(C)
    mismatch = objective(*lattice(bounded), bounded, n)
    x = np.r_[C.ravel(), rho]
    for tau in taus:
        x = minimize(mismatch, x, args=(tau,), jac=True, method='L-BFGS-B', options={'maxiter': iters}).x
    C = x[:3 * n].reshape(n, 3)
    if bounded:
        r = np.minimum(planeDistance(C).min(1) + H, x[3 * n:])
    else:
        r = x[3 * n:]
    return C, np.maximum(r, 0)


def monteCarlo(C, r, points=4_000_000, seed=7, chunk=500_000):
    """D of the exact geometry at uniform random points, and its standard error (from 4 batches)."""
    rng = np.random.default_rng(seed)
    lo = np.minimum(C.min(0) - r.max(), -0.52)
    hi = np.maximum(C.max(0) + r.max(), 0.52)
    batches = []
    for _ in range(4):
        a = b = both = 0
        for _ in range(points // chunk // 4):
            P = rng.uniform(lo, hi, (chunk, 3))
            inA = (P @ NORMALS.T - OFFSETS).max(1) <= 0
            cov = np.zeros(chunk, bool)
            for c, rr in zip(C, r):
                cov |= ((P - c) ** 2).sum(1) <= rr * rr
            a, b, both = a + inA.sum(), b + cov.sum(), both + (cov & inA).sum()
        batches.append(1 - 2 * both / (a + b))
    return float(np.mean(batches)), float(np.std(batches) / np.sqrt(len(batches) - 1))


def protrusion(C, r):
    return float((r - planeDistance(C).min(1)).max() / H)


def scored(tmp, mesh, C, r):
    path = os.path.join(tmp, 'found.csv')
    np.savetxt(path, np.c_[C, r], delimiter=',', header='x,y,z,r', comments='')
    c = run('compare', mesh, path)
    return float(c['dice'][0]), float(c['protrusion'][0]) / H


def randomStart(rng, n):
    out = []
    while len(out) < n:
        p = rng.uniform(-.5, .5, 3)
        if planeDistance(p[None, :]).min() > 0.02:
            out.append(p)
    C = np.array(out)
    return C, planeDistance(C).min(1) + H


def report(label, tmp, mesh, C, r, seconds):
    keep = r > 1e-6  # a ball the optimiser shrank away is no sphere (mss compare refuses r <= 0)
    C, r = C[keep], r[keep]
    label += ' (%d)' % len(r)
    d, se = monteCarlo(C, r)
    grid, prot = scored(tmp, mesh, C, r)
    print('%-33s D %.4f +- %.4f   mss compare %.4f   prot %.2f voxel (mss compare %.2f)   %4.0f s' % (
        label, d, se, grid, protrusion(C, r), prot, seconds), flush=True)
    return d


def engineSet(tmp, mesh, n, extra=()):
    out = os.path.join(tmp, 'engine.csv')
    run('generate', mesh, '-o', out, '--spheres', n, '--resolution', 103, *extra)
    e = np.loadtxt(out, delimiter=',', skiprows=1, ndmin=2)
    return e[:, :3], e[:, 3]


def polish(C, r, bounded):
    jitter = np.random.default_rng(5).normal(0, 0.003, C.shape)  # off the bound's kinks (ties of faces)
    return optimise(C + jitter, r, bounded)


def thirty(tmp, mesh, bounded, starts):
    """The engine's 30 spheres, polished, and the joint optimiser from random starts: (D, C, r) of the best."""
    mode = 'bounded' if bounded else 'unbounded'
    C, r = engineSet(tmp, mesh, N_SPHERES, () if bounded else ('--max-protrusion', 'inf'))
    found = [(report('%s: engine' % mode, tmp, mesh, C, r, 0), 0)]
    sets = [(C, r)]
    for label, seed in [('engine, polished', None)] + [('random start %d' % k, k) for k in range(starts)]:
        t = time.time()
        if seed is None:
            C, r = polish(C, r, bounded)
        else:
            C, r = optimise(*randomStart(np.random.default_rng(seed), N_SPHERES), bounded)
        found.append((report('%s: %s' % (mode, label), tmp, mesh, C, r, time.time() - t), len(sets)))
        sets.append((C, r))
    d, k = min(found)
    return (d, *sets[k])


def shaken(tmp, mesh, C, r, rounds):
    """Basin hopping from the polished set: every centre moved by 2 voxels (normal), polished again."""
    rng = np.random.default_rng(11)
    best = monteCarlo(C, r)[0]
    for k in range(rounds):
        t = time.time()
        Cn, rn = optimise(C + rng.normal(0, 2 * H, C.shape), r, True, taus=(1., .5, .3))
        d = report('bounded: shaken %d' % k, tmp, mesh, Cn, rn, time.time() - t)
        if d < best:
            best, C, r = d, Cn, rn
    return best


def counts(text):
    try:
        ns = [int(n) for n in text.split(',')]
    except ValueError:
        raise argparse.ArgumentTypeError('--counts takes sphere counts separated by commas, not %r' % text)
    if any(n < 1 for n in ns):
        raise argparse.ArgumentTypeError('--counts: a sphere count is at least 1, not %r' % text)
    return ns


def atLeastZero(text):
    if not text.isdigit():
        raise argparse.ArgumentTypeError('a whole number 0 or more, not %r' % text)
    return int(text)


def main():
    parser = argparse.ArgumentParser(description='the best spheres for the tetrahedron under the one-voxel bound')
    parser.add_argument('--starts', type=atLeastZero, default=6, help='random starts of the bounded search (default 6)')
    parser.add_argument('--shake', type=atLeastZero, default=6, help='basin-hopping rounds (default 6)')
    parser.add_argument('--counts', type=counts, default=[33, 35, 37, 38], help='other counts to polish')
    args = parser.parse_args()
    starts, rounds = args.starts, args.shake
    print('load: %s' % open('/proc/loadavg').read().strip())
    with tempfile.TemporaryDirectory() as tmp:
        mesh = os.path.join(tmp, 'tet.stl')
        tetrahedron(mesh, np.eye(3))
        bounded, C, r = thirty(tmp, mesh, True, starts)
        bounded = min(bounded, shaken(tmp, mesh, C, r, rounds))
        unbounded = thirty(tmp, mesh, False, max(2, starts // 3))[0]
        print('best D found at 30 spheres: bounded %.4f, unbounded %.4f (Monte Carlo; bar 0.09)' % (bounded,
                                                                                                  unbounded))
        for n in args.counts:  # how many spheres the bar takes under the bound
            C, r = engineSet(tmp, mesh, n)
            report('bounded, %d spheres: engine' % n, tmp, mesh, C, r, 0)
            t = time.time()
            report('bounded, %d spheres: polished' % n, tmp, mesh, *polish(C, r, True), time.time() - t)


if __name__ == '__main__':
    main()
