"""restoreClumpProperties: exact mass properties back after YADE recomputed a clump from its spheres."""

import gc
import warnings

import numpy as np

from .. import _mss
from ._clumps import _Plan, _checkMany, _clumpIds, _sphereMass, _withLoads, clumpIdList, yadeModules
from ._records import (OLD_TAG, attach, drop, encodeGrain, encodeMany, grainOf, labelOf, matchMembers,
                       quaternionMatrices, recordOf, scaled, scaleOf)


def _ids(func, clumpIds, O):
    """The clumps to restore, whether named by the caller, and the records already read ({id: record})."""
    if clumpIds is None:
        recs = {}
        for b in O.bodies:
            if b is not None and b.isClump and b.material is not None:
                rec = recordOf(b)
                if rec is not None:
                    recs[b.id] = rec
        return list(recs), False, recs
    return clumpIdList(func, clumpIds, O, existing=False), True, {}


def restoreClumpProperties(clumpIds=None, resolution=200):
    """Gives clumps their exact mass properties back after YADE recomputed them from their spheres
    (``O.bodies.updateClumpProperties``, ``releaseFromClump``, ``addToClump``) or after a density change
    (the material's density is read now; members' masses and inertias follow, as YADE's spheres).

    A clump from :func:`mssClump` (and friends) whose members are unchanged gets its grain's properties again
    (``mass='target'``: the grain's; ``'union'``: the union's), at the current density. A clump of ours whose
    members were released or added, and any other clump of spheres named in *clumpIds*, gets those of the union
    of its spheres (overlaps counted once, *resolution* voxels along the longest edge), and is remembered so
    from then on. A record that matches no clump any more (the clump was erased, or ``O.bodies.clear()`` gave
    its id to another clump) is dropped, with a warning where a clump holds the id now; it is never applied.
    The clumps' velocities and angular momenta are kept (the centre of mass may move: its velocity follows).

    :param clumpIds: clump ids; default every clump made by yade_mss in the scene
    :param int resolution: voxels along the longest edge of a union's grid
    :return: list of (clumpId, 'grain' or 'union')
    """
    func = 'restoreClumpProperties'
    utils, O, me = yadeModules()
    if isinstance(resolution, (bool, np.bool_)) or not isinstance(resolution, (int, np.integer)) or resolution < 2:
        raise ValueError('%s: resolution must be an integer >= 2, got %r' % (func, resolution))
    # Python's cyclic collector, run by the many small objects a restore makes, scans every live one each time:
    # with thousands of clumps it doubled the cost of the YADE calls alone. Nothing here makes cycles; it runs
    # again after.
    collecting = gc.isenabled()
    gc.disable()
    try:
        ids, explicit, recs = _ids(func, clumpIds, O)
        return _restore(func, O, me, ids, explicit, resolution, recs)
    finally:
        if collecting:
            gc.enable()


def _restore(func, O, me, ids, explicit, resolution, recs):
    if any(k.startswith(OLD_TAG) for k in O.tags.keys()):
        warnings.warn('%s: this scene holds records of an older yade-mss (O.tags mss.clump.*), which had no '
                      'fingerprint of their clumps: not read' % func, stacklevel=3)
    from yade.wrapper import Sphere
    V3 = me.Vector3
    found = []  # clumps to restore: (cid, body, member ids, members, radii, centres, densities, record, refs)
    quats = []  # members 0 and 1 (or 0 twice) of each, as (x, y, z, w)
    bodies, nBodies = O.bodies, len(O.bodies)
    for cid in ids:
        body = bodies[cid] if 0 <= cid < nBodies else None
        if body is None or not body.isClump:
            raise ValueError('%s: body %d is not a clump' % (func, cid))
        mids = sorted(body.shape.members)
        members, refs, radii, x, rho = [], [], [], [], []
        for i in mids:  # each member read once: what the loads need later is kept (Boost calls are the cost)
            b = bodies[i]
            sh, st = b.shape, b.state
            if not isinstance(sh, Sphere):
                raise ValueError('%s: member %d of clump %d is a %s, not a Sphere' % (func, b.id, cid, type(sh).__name__))
            members.append(b)
            refs.append((sh, st))
            radii.append(sh.radius)
            p = st.pos
            x.append((p[0], p[1], p[2]))
            rho.append(b.mat.density)
        if not rho[0] > 0:
            raise ValueError('%s: clump %d: the material density must be > 0, got %g' % (func, cid, rho[0]))
        for sh, st in (refs[0], refs[-1] if len(refs) == 1 else refs[1]):
            o = st.ori
            quats.append((o[0], o[1], o[2], o[3]))
        found.append((cid, body, mids, members, radii, x, rho, recs[cid] if cid in recs else recordOf(body), refs))
    if not found:
        return []
    R = quaternionMatrices(quats).reshape(-1, 2, 3, 3)
    same = _sameMembers(found, R)
    jobs, grown = [], {}
    for k, (cid, body, mids, members, radii, x, rho, rec, refs) in enumerate(found):
        how = 'same' if same[k] else None
        if rec and not same[k]:
            how = matchMembers(rec, mids, np.array(radii), np.array(x), R[k, 1])
        if how == 'scaled':  # grown alike about its centre (utils.growParticles): the record grows with it
            s = scaleOf(rec, mids, np.array(radii), np.array(x), R[k, 1])
            found[k] = found[k][:7] + (scaled(rec, s),) + found[k][8:]
            grown[cid] = _grownGrain(body, s)
            how = 'same'
        if rec is not None and how is None:
            warnings.warn('%s: the record of clump %d %s: dropped, not applied' % (
                func, cid, 'is not readable' if rec is False else
                'was made for another clump (the ids, radii or positions of its members differ)'), stacklevel=3)
            drop(body)
            if not explicit:
                continue
        jobs.append((k, how == 'same'))
    if not jobs:
        return []
    plans = _plans([found[k] for k, s in jobs if s], R[[k for k, s in jobs if s]])
    grains = iter(plans)
    work, spheres = [], {}
    for k, s in jobs:
        cid, body, mids, members, radii, x, rho, rec, refs = found[k]
        if s:
            plan, kind = next(grains), 'grain'
        else:  # in the clump's own frame (its first member at the origin), then moved back
            x0 = np.asarray(x[0], dtype=float)
            u = _mss.massSpheres((np.asarray(x, dtype=float) - x0).ravel().tolist(), radii, int(resolution))
            plan = _Plan.of(x, radii, u['volume'], np.array(u['centroid']) + x0, np.reshape(u['inertia'], (3, 3)))
            kind = 'union'
        st = body.state
        p, v, w = st.pos, st.vel, st.angVel
        before = ((p[0], p[1], p[2]), (v[0], v[1], v[2]), (w[0], w[1], w[2]))
        final = [spheres[rd] if rd in spheres else spheres.setdefault(rd, _sphereMass(rd[0], rd[1], V3))
                 for rd in zip(radii, rho)]
        work.append((cid, members, plan, rho[0], before, kind, final, refs, k,
                     s and len(members) > 1 and cid not in grown))
    wanted = set(w[0] for w in work)
    others = [i for i in _clumpIds(O) if i not in wanted]
    # the inertias are set too: the density may have changed, whatever the masses say
    _withLoads([(members, (rho * p.m).tolist(), [f[0] for f in final], [f[1] for f in final], True, rho * p.j, p.V,
                 refs) for cid, members, p, rho, before, kind, final, refs, k, kept in work],
               lambda: _aboutTheOrigin(O, me, work, lambda: O.bodies.updateClumpProperties(excludeList=others,
                                                                                           discretization=0)), me)
    states = [O.bodies[w[0]].state for w in work]
    rho = np.array([w[3] for w in work])
    _checkMany(func, [w[0] for w in work], states, rho * np.array([w[2].volume for w in work]),
               np.array([w[2].centroid for w in work]), rho[:, None] * np.array([w[2].moments for w in work]))
    # YADE's update zeroes the velocities: keep the motion (the centre of mass may have moved)
    pos0, vel0, w = (np.array([x[4][i] for x in work]) for i in range(3))
    C = np.array([x[2].centroid for x in work])
    vel = vel0 + np.cross(w, C - pos0)
    mom = rho[:, None] * np.einsum('kij,kj->ki', np.array([x[2].inertia for x in work]), w)
    for st, v, wi, L in zip(states, vel.tolist(), w.tolist(), mom.tolist()):
        st.vel, st.angVel, st.angMom = V3(*v), V3(*wi), V3(*L)
    done = [(x[0], x[5]) for x in work]
    # the record of an unchanged clump of several members holds as it was (its frame is member 1's, which did
    # not turn); the others' are written: a union's is new, a lone member's frame is member 0's, which turned
    write = [w for w in work if not w[9]]
    if write:
        texts = encodeMany([found[w[8]][2] for w in write], [np.asarray(found[w[8]][5]) for w in write],
                           [np.asarray(found[w[8]][4]) for w in write], np.array([w[2].volume for w in write]),
                           np.array([w[2].centroid for w in write]), np.array([w[2].inertia for w in write]),
                           [w[2].m for w in write], np.array([w[2].V for w in write]),
                           np.array([w[2].j for w in write]),
                           np.array([R[w[8], 1] if len(w[1]) > 1 else w[2].V.T for w in write]))
        from yade.wrapper import Material
        for w, text in zip(write, texts):  # a clump whose members changed is no longer its grain
            attach(O.bodies[w[0]], text, Material, '' if w[5] == 'union' else grown.get(w[0]))
    return done


def _grownGrain(body, s):
    """The grain a breakable clump carries, grown by *s* as its record (its mesh is in the record's frame, whose
    origin is member 0: it scales about it as the offsets do); None where it carries none; '' (dropped) where it
    is not readable: kept, it would stand at the old size (mssSplit then says the clump carries no grain)."""
    g = grainOf(labelOf(body))
    if g is False:
        return ''
    return encodeGrain(g[0] * s, g[1]) if g else None


def _aboutTheOrigin(O, me, work, action):
    """Runs *action* (YADE's sum of the members) with each clump of *work* moved so that its centre is at the
    origin, then moves them back: YADE sums the members' tensors about the origin and moves the sum to the
    centre, which cost eps M |C|^2 (a clump 1.2 km from the origin took its inertia 4.6e-7 off)."""
    moved = []
    for w in work:
        by = me.Vector3(*np.asarray(w[2].centroid, dtype=float).tolist())
        for sh, st in w[7]:
            st.pos = st.pos - by
        moved.append((w[0], w[7], by))
    try:
        return action()
    finally:
        for cid, refs, by in moved:
            st = O.bodies[cid].state
            st.pos = st.pos + by
            for sh, s in refs:
                s.pos = s.pos + by


def _sameMembers(found, R):
    """For each clump found, whether its members are exactly those of its record (ids, radii, positions in
    its frame): :func:`yade_mss._records.matchMembers`'s 'same', for all clumps at once."""
    out = np.zeros(len(found), dtype=bool)
    cand = [k for k, f in enumerate(found) if f[7] and f[7].ids == f[2]]
    if not cand:
        return out
    counts = np.array([len(found[k][4]) for k in cand])
    starts = np.concatenate([[0], np.cumsum(counts)[:-1]])
    which = np.repeat(np.arange(len(cand)), counts)
    X = np.array([p for k in cand for p in found[k][5]])
    radii = np.array([r for k in cand for r in found[k][4]])
    recRadii = np.concatenate([found[k][7].radii for k in cand])
    recRel = np.concatenate([found[k][7].rel for k in cand])
    F = R[cand, 1]
    rel = np.einsum('mi,mij->mj', X - X[starts][which], F[which])
    size = (np.maximum.reduceat(X, starts, axis=0) - np.minimum.reduceat(X, starts, axis=0)).max(axis=1) \
        + 2 * np.maximum.reduceat(radii, starts)
    posErr = np.maximum.reduceat(np.abs(rel - recRel).max(axis=1), starts)
    radErr = np.maximum.reduceat(np.abs(radii - recRadii), starts)
    out[cand] = (posErr <= 1e-9 * size) & (radErr <= 1e-12 * np.maximum.reduceat(radii, starts))
    return out


def _plans(found, R):
    """The recorded plans of clumps found unchanged, in the world now (R: members 0 and 1's rotations; the
    records are in member 1's frame, or member 0's alone)."""
    if not found:
        return []
    F = R[:, 1]
    x0 = np.array([f[5][0] for f in found])
    recs = [f[7] for f in found]
    C = x0 + np.einsum('kij,kj->ki', F, np.array([r.centroid for r in recs]))
    Irel = np.array([r.inertia for r in recs])
    I = np.einsum('kij,kjl,kml->kim', F, Irel, F)
    j, V = np.linalg.eigh(np.einsum('kij,kjl,kml->kim', F, np.array([r.J for r in recs]), F))
    flip = np.linalg.det(V) < 0
    V[flip, :, 2] *= -1
    moments = np.linalg.eigvalsh(Irel)
    out = []
    for k, r in enumerate(recs):
        p = _Plan()
        p.volume, p.m, p.centroid, p.inertia, p.j, p.V, p.moments = r.volume, r.m, C[k], I[k], j[k], V[k], moments[k]
        out.append(p)
    return out
