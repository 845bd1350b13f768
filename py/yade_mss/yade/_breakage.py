"""Grains that break during a YADE simulation into MSS fragments (the MSS paper's summary: shapes generated at
run time, particle fragmentation, a constraint plane for the fragmentation plane).

:func:`mssSplit` replaces a breakable clump (``mssClump(..., breakable=True)``: it carries its grain's mesh) by
one clump per piece of its grain on either side of a plane. Each piece is the grain cut and capped exactly
(:func:`yade_mss._mss.splitMesh`); its spheres are generated on it under the protrusion bound and kept off the
cut plane; its clump carries the piece's exact mass, centre and inertia. The pieces' mass properties sum to the
parent's (the same mesh, cut), so giving each piece the parent's velocity field (v + w x r, and w) keeps mass,
linear momentum and angular momentum about the common centre exactly.

:func:`MssBreakage` is the engine that breaks grains by a criterion each period: by default the characteristic
stress sigma = F / d^2 of the largest opposing pair of contact forces against a Weibull strength with a size
effect (McDowell and Bolton 1998; McDowell and Amon 2000: survival exp(-(d/d0)^3 (sigma/sigma0)^m)).
"""

import concurrent.futures
import inspect
import json
import math
import os
import warnings

import numpy as np

from .. import _mss
from ..base import integer, number, split as splitKeywords, vector3
from ..grains import GENERATE_OPTIONS, flatArray, generate, generateWith
from ._clumps import (_Members, _Plan, _build, _offsetWarning, bodyOptions, clumpIdList, matrix, stateTensor,
                      yadeModules)
from ._loads import memberLoads
from ._records import encodeGrain, grainOf, labelOf, matchMembers, quaternionMatrices, recordOf

LOG_TAG = 'mss.breakage'
_SPLIT_OWN = ('clumpId', 'plane', 'nSpheres', 'minSize', 'resolution')
_GENERATE_DEFAULTS = dict((k, p.default) for k, p in inspect.signature(generate).parameters.items() if k != 'source')
_SPLIT_GENERATE = tuple(k for k in GENERATE_OPTIONS if k not in ('nSpheres', 'planes', 'resolution'))


def _meshOf(d):
    return (np.frombuffer(d['vertices'], dtype=float).reshape(-1, 3),
            np.frombuffer(d['triangles'], dtype=np.int32).reshape(-1, 3))


def _members(func, O, cid):
    """(clump body, sorted member ids, member bodies, radii (n), positions (n, 3)) of clump *cid*."""
    from yade.wrapper import Sphere
    cid = integer(func, 'clumpId', cid, 0)
    body = O.bodies[cid] if cid < len(O.bodies) else None
    if body is None or not body.isClump:
        raise ValueError('%s: body %d is not a clump' % (func, cid))
    mids = sorted(body.shape.members)
    bodies = [O.bodies[i] for i in mids]
    for b in bodies:
        if not isinstance(b.shape, Sphere):
            raise ValueError('%s: member %d of clump %d is a %s, not a Sphere' % (func, b.id, cid,
                                                                               type(b.shape).__name__))
    radii = np.array([b.shape.radius for b in bodies])
    x = np.array([[b.state.pos[0], b.state.pos[1], b.state.pos[2]] for b in bodies])
    return body, mids, bodies, radii, x


def grainInWorld(func, O, cid):
    """The mesh of breakable clump *cid* where the clump is now: (vertices (n, 3), triangles (m, 3))."""
    x0, F, v, t = grainInFrame(func, O, cid)
    return x0 + v.dot(F.T), t


def grainInFrame(func, O, cid):
    """The mesh of breakable clump *cid* in its own frame (member 0's, as its record holds it), and that frame:
    (x0: member 0's position, F: its rotation, vertices (n, 3), triangles (m, 3)); a world point is x0 + F v.
    Its mass properties are computed there: far from the world's origin the world coordinates' rounding ate
    their digits (1e-10 relative at 52 m, 2.2e-8 at 1167 m)."""
    body, mids, bodies, radii, x = _members(func, O, cid)
    text = labelOf(body)
    rec = recordOf(body, text)
    if rec is None:
        raise ValueError('%s: clump %d was not made by yade-mss (it carries no grain): only clumps made with '
                         'mssClump(..., breakable=True) or mssClumpCloud(..., breakable=True) can break' % (func, cid))
    grain = grainOf(text) if rec else False
    if grain is None:
        raise ValueError('%s: clump %d carries no grain mesh: make it with breakable=True (from a mesh, two '
                         'spheres or more)' % (func, cid))
    if grain is False or rec is False:
        raise RuntimeError('%s: the record of clump %d is not readable' % (func, cid))
    o = bodies[1].state.ori
    F = quaternionMatrices([(o[0], o[1], o[2], o[3])])[0]
    if matchMembers(rec, mids, radii, x, F) != 'same':
        raise RuntimeError('%s: the members of clump %d are not those it was made with (spheres added, released '
                           'or moved): its grain no longer describes it' % (func, cid))
    v, t = grain
    return np.array(x[0], dtype=float), F, v, t


def _inWorld(mesh, x0, F):
    """A mesh of the grain's frame (x0, F: grainInFrame) in world coordinates."""
    return (x0 + np.asarray(mesh[0]).dot(F.T), mesh[1])


def _massInWorld(m, x0, F):
    """Mass properties of the grain's frame (volume, centroid, inertia about the centroid at unit density) in
    world coordinates: the centroid moved, the tensor turned."""
    I = np.reshape(m['inertia'], (3, 3))
    return dict(m, centroid=list(x0 + F.dot(np.asarray(m['centroid'], dtype=float))),
                inertia=list(F.dot(I).dot(F.T).ravel()))


def _plane(func, plane):
    try:
        point, normal = plane
    except (TypeError, ValueError):
        raise TypeError('%s: plane must be (point, normal), 3 numbers each, got %r' % (func, plane))
    p, n = vector3(func, 'plane point', point), vector3(func, 'plane normal', normal)
    if not np.linalg.norm(n) > 0:
        raise ValueError('%s: the plane normal must be non-zero' % func)
    return p, n / np.linalg.norm(n)


def _counts(func, nSpheres, parentCount, volumes, parentVolume):
    if nSpheres is None:  # by volume: the parent's spheres shared out; four reach any centre of mass
        return [max(4, int(round(parentCount * v / parentVolume))) for v in volumes]
    if callable(nSpheres):
        return [integer(func, 'nSpheres(volume, size)', nSpheres(v, _size(v)), 1, 65535) for v in volumes]
    n = integer(func, 'nSpheres', nSpheres, 1, 65535)
    return [n] * len(volumes)


def _size(volume):
    """The diameter of the sphere of this volume: a grain's size here (sieves see about that)."""
    return (6.0 * volume / math.pi) ** (1.0 / 3.0)


def _neighbours(O, ids):
    """The bodies within reach of the bodies *ids* (a clump's members), not one of them: [(body id, shift)],
    the shift putting the neighbour's image next to ours in a periodic cell. Found by distance, not by
    interactions: a piece's spheres may lie where the parent's did not, and pieces made earlier in the same
    step have no interactions yet. Walls always count (they are unbounded)."""
    from yade.wrapper import Box, Sphere, Wall
    mine = set(ids)
    x = np.array([[O.bodies[i].state.pos[a] for a in range(3)] for i in ids])
    rad = np.array([O.bodies[i].shape.radius for i in ids])
    c = x.mean(axis=0)
    reach = float(np.max(np.linalg.norm(x - c, axis=1) + rad))
    walls, found, pos, size = [], [], [], []
    # one pass of the fewest calls into YADE per body (each is a Boost call, ~0.3 us), the geometry after it
    # in numpy: 5200 bodies took 23 ms with numpy per body
    for b in O.bodies:
        if b is None or b.isClump:
            continue
        sh = b.shape
        if isinstance(sh, Sphere):
            s = sh.radius
        elif isinstance(sh, Wall):
            walls.append(b.id)
            continue
        elif isinstance(sh, Box):
            e = sh.extents
            s = math.sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2])
        else:
            continue
        p = b.state.pos
        found.append(b.id)
        pos.append((p[0], p[1], p[2]))
        size.append(s)
    out = [(i, np.zeros(3)) for i in walls if i not in mine]
    if not found:
        return out
    d = np.array(pos) - c
    if O.periodic:  # the nearest image
        H = np.array([[O.cell.hSize[i, j] for j in range(3)] for i in range(3)])
        shift = -np.round(np.linalg.solve(H, d.T)).T.dot(H.T)
    else:
        shift = np.zeros_like(d)
    close = np.linalg.norm(d + shift, axis=1) < 1.5 * reach + np.array(size)
    out += [(found[k], shift[k]) for k in np.flatnonzero(close) if found[k] not in mine]
    return out


def _contactPoints(O, ids):
    """Where the bodies *ids* touch others: [(point, normal into them)], from the real interactions' ScGeom.
    A piece's spheres are made to reach those of its side, so that a split keeps the grain's contacts."""
    mine = set(ids)
    out = []
    for i in ids:
        for it in O.interactions.withBody(i):
            if not it.isReal:
                continue
            j = it.id2 if it.id1 == i else it.id1
            g = it.geom
            if j in mine or not hasattr(g, 'normal'):
                continue
            n = np.array([g.normal[0], g.normal[1], g.normal[2]])  # from id1 towards id2
            p = g.contactPoint
            out.append((np.array([p[0], p[1], p[2]]), -n if it.id1 == i else n))
    return out


def _gaps(O, near, c):
    """For each point of *c* (n, 3), its distance to the nearest surface of the bodies *near*
    (:func:`_neighbours`), negative inside one; Sphere, Wall and Box shapes (others: infinity)."""
    from yade.wrapper import Box, Sphere, Wall
    gap = np.full(len(c), np.inf)
    for j, shift in near:
        b = O.bodies[j]
        if b is None:
            continue
        sh, p = b.shape, np.array([b.state.pos[0], b.state.pos[1], b.state.pos[2]]) + shift
        if isinstance(sh, Sphere):
            g = np.linalg.norm(c - p, axis=1) - sh.radius
        elif isinstance(sh, Wall):
            g = np.abs(c[:, sh.axis] - p[sh.axis])
        elif isinstance(sh, Box):
            e = np.array([sh.extents[0], sh.extents[1], sh.extents[2]])
            q = np.abs((c - p).dot(matrix(b.state.ori)))  # in the box's frame; by symmetry its first octant
            out = np.linalg.norm(np.maximum(q - e, 0), axis=1)
            g = np.where(out > 0, out, -np.min(e - q, axis=1))
        else:
            continue
        gap = np.minimum(gap, g)
    return gap


def _depths(O, near, c, r):
    """How deep spheres (centres (n, 3), radii (n)) reach into each body of *near*: an array, 0 where they
    do not touch it."""
    return np.array([max(0.0, float(np.max(r - _gaps(O, [nb], c)))) if len(r) else 0.0 for nb in near])


def _within(O, near, depth, c, r, least=0.0):
    """The spheres (c, r) shrunk so that none reaches deeper into a neighbour than the parent did (*depth*, per
    neighbour; 0: not touching it): a piece must not push its neighbours harder than the grain did. A sphere
    that would keep less than a quarter of its radius, or end below *least* (the rMin asked for: the smallest
    sphere sets the time step and the softest contact), goes (the largest share stays, whatever it is)."""
    allowed = r.copy()
    for nb, d in zip(near, depth):
        allowed = np.minimum(allowed, _gaps(O, [nb], c) + d)
    keep = (allowed >= 0.25 * r) & (allowed >= least)
    if not keep.any():
        keep[np.argmax(allowed / r)] = True
    return c[keep], np.maximum(allowed[keep], 1e-3 * r[keep])


def _log(O, event):
    """Appends *event* to the breakage log in O.tags (saved with the scene)."""
    old = O.tags[LOG_TAG] if LOG_TAG in O.tags.keys() else ''
    O.tags[LOG_TAG] = old + json.dumps(event, sort_keys=True) + '\n'


def breakageLog():
    """The splits of this scene so far (:func:`mssSplit`, :func:`MssBreakage`), oldest first: a dict each, with
    iter, time, parent, parentVolume, pieces (clump ids), volumes, sizes (diameters of the spheres of their
    volumes), spheres (counts), plane (point, normal), reachBefore/reachAfter (the deepest overlap of the
    parent's and the pieces' spheres into their neighbours) and, from the engine, sigma and strength."""
    utils, O, me = yadeModules()
    text = O.tags[LOG_TAG] if LOG_TAG in O.tags.keys() else ''
    return [json.loads(line) for line in text.splitlines() if line.strip()]


def mssSplit(clumpId, plane, nSpheres=None, minSize=0.0, resolution=40, **options):
    """Breaks a clump in two (or more) along a plane: the clump is replaced by one clump per piece of its grain
    on either side. Each piece is the grain cut and capped exactly; its spheres are generated on it (under the
    protrusion bound, off the cut plane); its clump has the piece's exact mass, centre and inertia and moves as
    the parent's body did there (v + w x r, w), so that mass, linear momentum and angular momentum about the
    common centre are kept exactly. The pieces can break again.

    :param int clumpId: a clump made with ``breakable=True`` (:func:`mssClump`, :func:`mssClumpCloud`) or a piece
    :param plane: (point, normal) in world coordinates; a plane that misses the grain is an error
    :param nSpheres: spheres a piece: None (the parent's count shared by volume, at least 4), an int, or a
        callable (volume, size) -> int. A clump's centre of mass lies in the span of its sphere centres (YADE
        sums them), so with 2 or 3 spheres it may miss the piece's by a little (a warning gives the distance)
    :param float minSize: a piece smaller than this (the diameter of the sphere of its volume) becomes a
        single sphere at its centre of mass (reaching the piece's nearest surface point) and does not break
        again
    :param int resolution: generation grid of each piece, voxels along its shortest bounding-box edge. The
        protrusion bound is a voxel of it; 40 (the default) scored D 2% lower than 50 on an independent grid, in
        0.7x the time, with bumps of at most 1/40 of the piece's shortest edge (``bench/pieces.py``)
    :param options: :func:`generate` keywords (method, rMin, supersample, ...) and ``utils.sphere`` ones for the
        members (default: the parent's material and mask; colours random as for any clump). The pieces are
        generated side by side, one per core; ``threads=1`` generates them one after another (the same spheres)
    :return: [(clumpId, [memberIds])], one per piece; O.bodies is unchanged if anything fails

    A piece's spheres reach no deeper into each neighbour (Sphere, Wall and Box bodies near the grain) than
    the parent's did, and touch none it did not touch: those that would are shrunk (the log has both depths:
    :func:`breakageLog`), so a split does not push neighbours harder than the grain did. A sphere shrunk below
    ``rMin`` or ``rMinVoxels`` (when given) or a quarter of its radius is dropped instead: the smallest sphere
    sets the time step.
    """
    return _split('mssSplit', clumpId, plane, nSpheres, minSize, resolution, options, {})


def _split(func, clumpId, plane, nSpheres, minSize, resolution, options, info):
    gen, body = splitKeywords(func, options, _SPLIT_GENERATE, bodyOptions(),
                              extra=_SPLIT_OWN)
    utils, O, me = yadeModules()
    point, normal = _plane(func, plane)
    minSize = number(func, 'minSize', minSize, 0.0)
    resolution = integer(func, 'resolution', resolution, 1)
    x0, F, v, t = grainInFrame(func, O, clumpId)
    parent, mids, bodies, radii, x = _members(func, O, clumpId)
    # cut in the grain's own frame, where its record holds it: the pieces' mass properties keep their digits
    # however far the grain is from the origin, and every generation of pieces sums to its parent to rounding
    cut = _mss.splitMesh(flatArray(v), flatArray(t, np.int64), list(F.T.dot(point - x0)) + list(F.T.dot(normal)))
    if not cut['above'] or not cut['below']:
        raise ValueError('%s: the plane misses the grain of clump %d (all of it lies on one side)'
                         % (func, parent.id))
    local = [_meshOf(d) for d in cut['above'] + cut['below']]
    sides = [(_inWorld(m, x0, F), 1.0 if k < len(cut['above']) else -1.0) for k, m in enumerate(local)]
    props = [_massInWorld(d['mass'], x0, F) for d in cut['above'] + cut['below']]
    volumes = [p['volume'] for p in props]
    counts = _counts(func, nSpheres, len(mids), volumes, sum(volumes))
    near = _neighbours(O, mids)
    depthBefore = _depths(O, near, x, radii)
    reachBefore = float(depthBefore.max()) if len(near) else 0.0
    touching = _contactPoints(O, mids)
    def piece(k):
        (mesh, sign), pr = sides[k], props[k]
        n = 1 if _size(pr['volume']) < minSize else counts[k]
        mine = [list(q) + list(m) for q, m in touching if sign * (q - point).dot(normal) > 0]
        where = '%s: clump %d, piece %d (volume %g)' % (func, parent.id, k, pr['volume'])
        pc, pr_, n, least = _pieceSpheres(where, mesh, pr, n, gen, resolution, (point, sign * normal), mine)
        # off the cut plane, whatever reached a contact point: pieces must not overlap each other
        pr_ = np.minimum(pr_, np.maximum(sign * (pc - point).dot(normal), 0.0))
        pc, pr_ = _holdCentroid(mesh, pr, pc, pr_)
        pc, pr_ = _within(O, near, depthBefore, pc, pr_, least)
        # the grain as its record holds it (in member 0's frame), encoded here: zlib lets the others run
        # turned in the small numbers of the grain's frame, then moved as a whole: its vertices rounded alike, so
        # its volume and tensor stay the piece's own to the next generation (world coordinates, each vertex
        # rounded on its own, moved the next split's sums by 1e-13 at 1.2 km)
        v = local[k][0]
        grain = encodeGrain(v.dot(F.T) + (x0 - pc[0]), mesh[1]) if n > 1 and len(pc) > 1 else None
        return _Plan.of(pc, pr_, pr['volume'], np.array(pr['centroid']), np.reshape(pr['inertia'], (3, 3))), grain

    done = _sideBySide([lambda k=k: piece(k) for k in range(len(sides))], gen.get('threads'))
    plans, grains = [p for p, g in done], [g for p, g in done]
    st = parent.state
    c = np.array([st.pos[0], st.pos[1], st.pos[2]])
    v = np.array([st.vel[0], st.vel[1], st.vel[2]])
    # the spin from the angular momentum YADE integrates (angVel lags it by half a step in its leapfrog): the
    # pieces' spins then sum with their orbits to the parent's angular momentum exactly
    L = np.array([st.angMom[0], st.angMom[1], st.angMom[2]])
    w = np.linalg.solve(stateTensor(st), L) if np.any(L) else np.array([st.angVel[0], st.angVel[1], st.angVel[2]])
    blocked = st.blockedDOFs
    body.setdefault('material', bodies[0].mat)
    body.setdefault('mask', bodies[0].mask)
    made = _build(func, plans, _Members(func, body), _offsetWarning, grains)
    V3 = me.Vector3
    rho = O.bodies[made[0][1][0]].mat.density
    for (cid, ids), p in zip(made, plans):
        s = O.bodies[cid].state
        s.vel = V3(*(v + np.cross(w, p.centroid - c)))
        s.angVel = V3(*w)
        s.angMom = V3(*(rho * p.inertia.dot(w)))
        if blocked:
            s.blockedDOFs = blocked
    O.bodies.erase(parent.id, True)
    # bodies erased and appended in one step left YADE 2023.02a's periodic insertion sort (insertionSortPeri)
    # in an endless loop at the next step; a full sort once (doSort resets itself) starts it afresh
    from yade.wrapper import InsertionSortCollider
    for e in O.engines:
        if isinstance(e, InsertionSortCollider):
            e.doSort = True
    reachAfter = max(float(_depths(O, near, p.centers, p.radii).max()) if len(near) else 0.0 for p in plans)
    event = dict(iter=O.iter, time=O.time, parent=parent.id, parentVolume=float(sum(volumes)),
                 pieces=[cid for cid, ids in made], volumes=volumes, sizes=[_size(vv) for vv in volumes],
                 spheres=[len(ids) for cid, ids in made], plane=[list(point), list(normal)],
                 reachBefore=reachBefore, reachAfter=reachAfter, **info)
    _log(O, event)
    scale = _size(sum(volumes))
    if reachAfter > max(reachBefore, 0.0) + 1e-9 * scale:
        warnings.warn('%s: the pieces of clump %d reach %.3g into a neighbour, the parent reached %.3g'
                      % (func, parent.id, reachAfter, reachBefore), stacklevel=2)
    return made


def _sideBySide(calls, threads):
    """The results of *calls* (the pieces of a split), run side by side on the cores: a piece's grid is small, so
    its generation runs on one thread (OmpScope::forGrid), and the binding (and zlib) let the others run
    meanwhile. *threads* = 1 (the generation's option) runs them one after another; the spheres are the same
    either way."""
    global _pool
    if len(calls) < 2 or threads == 1 or (os.cpu_count() or 1) < 2:
        return [c() for c in calls]
    # kept: starting a thread waits for the interpreter's lock, up to its switch interval; a forked process has
    # none of its parent's threads, so it starts its own
    if _pool is None or _pool[0] != os.getpid():
        _pool = (os.getpid(), concurrent.futures.ThreadPoolExecutor(max_workers=(os.cpu_count() or 2) - 1,
                                                                    thread_name_prefix='mssSplit'))
    rest = [_pool[1].submit(c) for c in calls[1:]]
    try:
        first = calls[0]()  # this thread works too
    finally:  # nothing of this split still runs when it returns or raises
        concurrent.futures.wait(rest)
    return [first] + [f.result() for f in rest]


_pool = None  # (the process it was started in, the pool)


def _holdCentroid(mesh, props, c, r):
    """The spheres (c, r) of a piece, with one more at its centre of mass where that lies outside the hull of
    their centres and inside the piece. There the loads that give YADE the exact centre mix large positive and
    negative masses, and YADE's sums, which it takes about the world's origin, lose their precision (a sliver of
    the femur, 4 spheres: masses from -384 to +217 times the piece's, principal moments 1% off). A sphere at the
    centre, reaching the nearest surface point, takes the mass there."""
    if len(r) < 2:
        return c, r
    volume = float(props['volume'])
    loads = memberLoads(c, r, volume, props['centroid'], np.reshape(props['inertia'], (3, 3)))
    if np.abs(loads.m).sum() <= 1.5 * volume:
        return c, r
    centroid = np.array(props['centroid'], dtype=float)
    room = _mss.insideClearance(flatArray(mesh[0]), flatArray(mesh[1], np.int64), list(centroid))
    if not room > 0:  # a bent piece: its centre of mass is outside it
        return c, r
    return np.vstack([c, centroid[None, :]]), np.append(r, room)


def _pieceSpheres(where, mesh, props, n, gen, resolution, plane, contacts):
    """The spheres of one piece (*mesh*, its mass properties *props*), *n* of them, and the radius below which
    a neighbour may not shrink them: (centres, radii, n, least). One sphere sits at the centre of mass, so
    that the clump's is exact, reaching the nearest surface point; so does a piece too thin for the rMin
    asked for (no sphere of that size fits), which then breaks no more, as one below minSize."""
    centroid = np.array(props['centroid'])
    if n == 1:
        room = _mss.insideClearance(flatArray(mesh[0]), flatArray(mesh[1], np.int64), list(centroid))
        if room > 0:
            return centroid[None, :], np.array([room]), 1, 0.0
    given = dict(_GENERATE_DEFAULTS, **gen)
    given.update(nSpheres=n, resolution=resolution, planes=[(tuple(plane[0]), tuple(plane[1]))])
    if n == 1:  # the centre of mass is outside (a bent piece): the largest sphere, whatever rMin
        given.update(rMin=None, rMinVoxels=None)
    try:
        # the piece lies on its side of the plane: its own mass properties are the target's
        r = generateWith(mesh, given, contactPoints=contacts if given['contacts'] else [], target=props)
    except ValueError as e:
        if n > 1 and 'largest inscribed radius' in str(e):
            return _pieceSpheres(where, mesh, props, 1, gen, resolution, plane, contacts)
        raise ValueError('%s: %s' % (where, e))
    except RuntimeError as e:
        raise RuntimeError('%s: %s' % (where, e))
    # the generation's own bound: rMin, or rMinVoxels on the piece's grid (the larger)
    least = max(given['rMin'] or 0.0, (given['rMinVoxels'] or 0.0) * r.grid['voxelSize']) if n > 1 else 0.0
    return r.centers, r.radii, n, least


# the engines' parameters that cannot go into their command (callables), by label: MssBreakage again after
# loading a scene in a new process
_callables = {}


def MssBreakage(iterPeriod=100, sigma0=None, modulus=3.0, d0=None, seed=0, criterion=None, nSpheres=None,
                minSize=0.0, resolution=40, label='mssBreakage', **options):
    """An engine (a ``PyRunner``; add it to ``O.engines`` after the NewtonIntegrator) that breaks grains each
    *iterPeriod* steps: every breakable clump (``breakable=True``) that fails the criterion is split
    (:func:`mssSplit`) along its plane, and the split is logged (:func:`breakageLog`).

    Built-in criterion (crushing of grains, McDowell and Bolton 1998): the characteristic stress
    sigma = F / d^2, where F is the larger of the two forces of the most opposing pair of contact forces on the
    grain (for each pair a, b: min(f_a . u, -f_b . u) along u = (f_a - f_b) / norm(f_a - f_b)) and d the diameter of
    the sphere of the grain's volume; the grain breaks when sigma reaches its strength, drawn once per grain from
    the Weibull distribution with a size effect, survival exp(-(d / d0)^3 (sigma / sigma0)^m) (McDowell and
    Amon 2000): strength = sigma0 (d / d0)^(-3/m) (-ln U)^(1/m), U uniform from (*seed*, the clump's id, its
    first member's id), so a scene saved and loaded draws the same. The plane goes through the centre of mass
    and contains the loading direction u, turned about it at random (same seed).

    :param int iterPeriod: steps between checks
    :param float sigma0: the Weibull scale stress at size d0 (37% of grains of size d0 survive sigma0)
    :param float modulus: the Weibull modulus m
    :param float d0: the reference size (world units)
    :param int seed: the strengths' and planes' seed
    :param criterion: instead of the built-in one, a callable (clumpId, contacts) -> None (no break) or a
        plane (point, normal); contacts: a list of (point, force on the grain), numpy arrays. Not saved with
        the scene: after ``O.load`` in a new process, call MssBreakage again with the same label
    :param nSpheres: spheres a piece, as in :func:`mssSplit`
    :param float minSize: as in :func:`mssSplit`: smaller pieces are single spheres and never break
    :param int resolution: as in :func:`mssSplit`
    :param str label: the engine's label
    :param options: :func:`mssSplit`'s generate and body keywords
    :return: the engine (``yade.wrapper.PyRunner``)
    """
    func = 'MssBreakage'
    splitKeywords(func, options, _SPLIT_GENERATE, bodyOptions(),
                  extra=('iterPeriod', 'sigma0', 'modulus', 'd0', 'seed', 'criterion', 'nSpheres', 'minSize',
                         'resolution', 'label'))
    from yade.wrapper import PyRunner
    iterPeriod = integer(func, 'iterPeriod', iterPeriod, 1)
    if criterion is not None and not callable(criterion):
        raise TypeError('%s: criterion must be a callable (clumpId, contacts) -> plane or None, got %r'
                        % (func, criterion))
    if criterion is None:
        if sigma0 is None or d0 is None:
            raise ValueError('%s: the built-in criterion needs sigma0 and d0 (or give a criterion)' % func)
        sigma0 = number(func, 'sigma0', sigma0)
        d0 = number(func, 'd0', d0)
        modulus = number(func, 'modulus', modulus)
        for name, val in (('sigma0', sigma0), ('d0', d0), ('modulus', modulus)):
            if not val > 0:
                raise ValueError('%s: %s must be > 0, got %r' % (func, name, val))
    if not isinstance(label, str) or not label.isidentifier():
        raise ValueError('%s: label must be a Python identifier, got %r' % (func, label))
    if nSpheres is not None and not callable(nSpheres):
        nSpheres = integer(func, 'nSpheres', nSpheres, 1, 65535)
    minSize = number(func, 'minSize', minSize, 0.0)
    resolution = integer(func, 'resolution', resolution, 1)
    seed = integer(func, 'seed', seed, 0)
    kept = {k: v for k, v in options.items() if k != 'material'}
    try:
        json.dumps(kept)
    except TypeError:
        raise TypeError('%s: the generate and body options must be numbers, strings or lists (they are saved '
                        'with the engine)' % func)
    _callables[label] = dict(criterion=criterion, nSpheres=nSpheres if callable(nSpheres) else None,
                             material=options.get('material'))
    cfg = dict(sigma0=sigma0, modulus=modulus, d0=d0, seed=seed, custom=criterion is not None,
               nSpheres=None if callable(nSpheres) else nSpheres, minSize=minSize, resolution=resolution,
               options=kept, callables=callable(nSpheres) or criterion is not None or 'material' in options)
    command = 'import yade_mss.yade as _mssy; _mssy.breakageStep(%r, %r)' % (label, json.dumps(cfg, sort_keys=True))
    return PyRunner(command=command, iterPeriod=iterPeriod, label=label)


def contactsByClump(O):
    """The contact forces on each clump: {clump id: [(contact point, force on the clump)]}, numpy arrays.
    Forces are YADE's normalForce + shearForce, which act on id2 (and the opposite on id1)."""
    rows = {}
    bodies = O.bodies
    # the fewest calls into YADE per contact, numbers gathered as floats and made arrays once per clump (numpy per
    # contact was most of a check: 13 us a contact)
    for i in O.interactions:
        if not i.isReal:
            continue
        ph = i.phys
        try:
            f = ph.normalForce + ph.shearForce
        except AttributeError:
            continue
        p = i.geom.contactPoint
        row = (p[0], p[1], p[2], f[0], f[1], f[2])
        for j, sign in ((i.id1, -1.0), (i.id2, 1.0)):
            b = bodies[j]
            if b.isClumpMember:
                rows.setdefault(b.clumpId, []).append((sign, row))
    out = {}
    for cid, rs in rows.items():
        a = np.array([r for s, r in rs])
        a[:, 3:] *= np.array([s for s, r in rs])[:, None]
        out[cid] = [(a[k, :3], a[k, 3:]) for k in range(len(a))]
    return out


def opposingPair(contacts):
    """(F, u): the most opposing pair of contact forces on a grain (the larger of min(f_a . u, -f_b . u) over
    pairs, u = (f_a - f_b) / norm(f_a - f_b)) and its direction; (0, None) without one."""
    if len(contacts) < 2:
        return 0.0, None
    f = np.array([c[1] for c in contacts])
    d = f[:, None, :] - f[None, :, :]
    n = np.linalg.norm(d, axis=2)
    n[n == 0] = np.inf
    u = d / n[:, :, None]
    a = np.einsum('ik,ijk->ij', f, u)   # f_a . u_ab
    b = -np.einsum('jk,ijk->ij', f, u)  # -f_b . u_ab
    m = np.minimum(a, b)
    k = np.unravel_index(np.argmax(m), m.shape)
    if not m[k] > 0:
        return 0.0, None
    return float(m[k]), u[k]


def weibullStrength(sigma0, modulus, d0, d, u):
    """The strength of a grain of size *d* for the uniform number *u* in (0, 1): sigma0 (d/d0)^(-3/m)
    (-ln u)^(1/m), the inverse of survival exp(-(d/d0)^3 (sigma/sigma0)^m)."""
    return sigma0 * (d / d0) ** (-3.0 / modulus) * (-math.log(u)) ** (1.0 / modulus)


def _uniform(seed, cid, first):
    return float(np.random.default_rng([seed, cid, first]).uniform(1e-300, 1.0))


def step(label, cfgText):
    """One check of engine *label* (its command calls this): the clumps that fail the criterion are split."""
    cfg = json.loads(cfgText)
    extra = _callables.get(label)
    if extra is None:
        if cfg['callables']:
            raise RuntimeError('MssBreakage %s: its criterion, nSpheres rule or material are not saved with the '
                               'scene: call MssBreakage(..., label=%r) again after loading' % (label, label))
        extra = dict(criterion=None, nSpheres=None, material=None)
    utils, O, me = yadeModules()
    breaks = []
    found = contactsByClump(O)
    if extra['criterion'] is not None:  # every clump: a user's criterion may not need contacts
        found = dict((b.id, found.get(b.id, [])) for b in O.bodies if b is not None and b.isClump)
    for cid, contacts in sorted(found.items()):
        body = O.bodies[cid]
        first = min(body.shape.members)
        if extra['criterion'] is not None:
            plane = extra['criterion'](cid, contacts)
            if plane is not None:
                breaks.append((cid, first, plane, {}))
            continue
        F, u = opposingPair(contacts)
        if F <= 0:
            continue
        rho = O.bodies[first].mat.density
        d = _size(body.state.mass / rho)
        sigma = F / d ** 2
        strength = weibullStrength(cfg['sigma0'], cfg['modulus'], cfg['d0'], d, _uniform(cfg['seed'], cid, first))
        if sigma < strength:
            continue
        t = np.random.default_rng([cfg['seed'], cid, first, O.iter]).normal(size=3)
        n = np.cross(u, t)
        c = body.state.pos
        breaks.append((cid, first, ((c[0], c[1], c[2]), n / np.linalg.norm(n)),
                       dict(sigma=sigma, strength=strength, force=F, direction=[float(x) for x in u])))
    options = dict(cfg['options'])
    if extra['material'] is not None:
        options['material'] = extra['material']
    nSpheres = extra['nSpheres'] if extra['nSpheres'] is not None else cfg['nSpheres']
    for cid, first, plane, info in breaks:
        # read only for the clumps that fail (no cache: ids come back after O.reset or erase); a clump without
        # a grain (a single-sphere fragment, a clump of YADE's) stays whole
        if grainOf(labelOf(O.bodies[cid])) is None:
            continue
        try:
            _split('MssBreakage', cid, plane, nSpheres, cfg['minSize'], cfg['resolution'], options, info)
        except ValueError as e:  # a plane that misses a thin grain: it stays whole this time
            if 'misses the grain' not in str(e):
                raise
            warnings.warn('MssBreakage: clump %d not split: %s' % (cid, e))


def grainSizes(clumpIds=None):
    """(sizes, masses) of the scene's clumps (default: all): the diameter of the sphere of each clump's volume
    (mass over its members' density) and its mass, numpy arrays. For grading curves (:func:`relativeBreakage`).

    :param clumpIds: the clumps to measure (default None: every clump of the scene)
    """
    utils, O, me = yadeModules()
    clumpIds = clumpIdList('grainSizes', clumpIds, O)
    masses, sizes = [], []
    for c in clumpIds:
        b = O.bodies[c]
        rho = O.bodies[min(b.shape.members)].mat.density
        masses.append(b.state.mass)
        sizes.append(_size(b.state.mass / rho))
    return np.array(sizes), np.array(masses)


def breakagePotential(sizes, masses, cutoff):
    """Hardin's (1985) breakage potential of a grading: the area between its curve (mass fraction finer against
    log10 size) and the vertical line at *cutoff* (Hardin: 0.074 mm, the silt limit), over sizes above it; for
    grains of sizes d_i and masses m_i, sum (m_i / M) max(0, log10(d_i / cutoff)).

    :param sizes: the grains' sizes (any one length unit, the cutoff's)
    :param masses: their masses
    :param float cutoff: the size below which grains count as broken as far as they can be
    """
    try:
        sizes, masses = np.asarray(sizes, dtype=float), np.asarray(masses, dtype=float)
    except (TypeError, ValueError):
        raise TypeError('breakagePotential: sizes and masses must be lists of numbers') from None
    cutoff = number('breakagePotential', 'cutoff', cutoff)
    if sizes.ndim != 1 or masses.ndim != 1 or sizes.shape != masses.shape:
        raise ValueError('breakagePotential: sizes and masses must be two lists of the same length, got %s and %s'
                         % (sizes.shape, masses.shape))
    if not (np.all(np.isfinite(sizes)) and np.all(np.isfinite(masses)) and np.all(masses >= 0)):
        raise ValueError('breakagePotential: sizes and masses must be finite, masses >= 0')
    if not (cutoff > 0 and sizes.size and np.all(sizes > 0) and masses.sum() > 0):
        raise ValueError('breakagePotential: sizes and masses of at least one grain, and a cutoff > 0')
    return float((masses * np.maximum(0.0, np.log10(sizes / cutoff))).sum() / masses.sum())


def relativeBreakage(before, after, cutoff):
    """Hardin's relative breakage B_r = B_t / B_p: the total breakage (the potential lost, the area between the
    gradings before and after) over the potential before.

    :param before: (sizes, masses) of the grading before, as :func:`grainSizes` gives
    :param after: (sizes, masses) after
    :param float cutoff: as in :func:`breakagePotential`
    """
    for name, g in (('before', before), ('after', after)):
        if isinstance(g, (str, bytes)) or not hasattr(g, '__len__') or len(g) != 2:
            raise TypeError('relativeBreakage: %s must be (sizes, masses), as grainSizes gives, got %r' % (name, g))
    bp = breakagePotential(before[0], before[1], cutoff)
    if not bp > 0:
        raise ValueError('relativeBreakage: no grain above the cutoff before: no breakage potential')
    return (bp - breakagePotential(after[0], after[1], cutoff)) / bp
