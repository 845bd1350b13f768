"""YADE clumps whose members are exactly the generated spheres, with the mass properties asked for.

How (YADE 2023.02a, stock, through its Python API; see :mod:`yade_mss._loads` for the sums): while YADE sums
the members (``appendClumped``, ``updateClumpProperties``), each member wears a temporary non-spherical shape
(a zero-size ``Box``) and carries the mass chosen for it, one member also a tensor and an orientation, so that
YADE's own sums give the wanted mass, centre of mass and inertia tensor, and YADE itself places the clump in the
principal frame and records the members' relative positions. Then the ``Sphere`` shapes come back and every
member keeps its share of the mass (positive, adding up to the clump's). Nothing recomputes a clump's mass
properties on steps, ``O.save``/``O.load`` or ``loadTmp``; only ``updateClumpProperties``, ``addToClump`` and
``releaseFromClump`` do, and those sum spheres as YADE always does (see :func:`restoreClumpProperties`).

Why not an extra member: a correction body (tried first) breaks YADE's clump API (release, erase, exporters).
Why not a C++ extension against YADE's headers: Debian ships none, and a fork's headers tie the package to
Debian's binary layout.

Each clump's exact properties (unit density, in the frame of its first member) are kept in ``O.tags`` under
``mss.clump.<id>``, which YADE saves with the scene, so :func:`restoreClumpProperties` works after
``O.save``/``O.load`` and ``loadTmp`` too.
"""

import inspect
import json
import math

import numpy as np

from . import _mss
from ._generate import GENERATE_OPTIONS, generate
from ._keywords import split
from ._loads import memberLoads
from ._results import MssResult

TAG = 'mss.clump.'


def _yade():
    try:
        from yade import utils
        from yade.wrapper import Omega
        import yade.minieigenHP as me
    except ImportError:
        raise RuntimeError('this function builds YADE bodies: run the script with yade (yade -n -x script.py)')
    return utils, Omega(), me


_bodyOptions = []


def bodyOptions():
    """The body keywords of ``utils.sphere`` (material, color, mask, fixed, wire, highlight, ...)."""
    if not _bodyOptions:
        utils, O, me = _yade()
        _bodyOptions.extend(p for p in inspect.signature(utils.sphere).parameters if p not in ('center', 'radius'))
    return tuple(_bodyOptions)


def matrix(q):
    """3x3 numpy rotation matrix of a YADE Quaternion."""
    m = q.toRotationMatrix()
    return np.array([[m[i, j] for j in range(3)] for i in range(3)])


def stateTensor(state):
    """Inertia tensor (world axes, about the centre of mass) of a YADE State."""
    R = matrix(state.ori)
    return R.dot(np.diag([state.inertia[0], state.inertia[1], state.inertia[2]])).dot(R.T)


def randomRotation(rng):
    """A rotation matrix uniformly distributed over SO(3) (a normalised Gaussian quaternion)."""
    w, x, y, z = rng.normal(size=4)
    return quaternionMatrix((w, x, y, z))


def quaternionMatrix(q):
    w, x, y, z = np.asarray(q, dtype=float) / np.linalg.norm(q)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def rotation(orientation, seed=None):
    """3x3 rotation matrix from None, 'random' (uniform, *seed*), a YADE Quaternion, (axis, angle), a 3x3
    matrix or (w, x, y, z)."""
    if orientation is None:
        return np.eye(3)
    if isinstance(orientation, str):
        if orientation != 'random':
            raise ValueError("orientation: a string must be 'random', got %r" % (orientation,))
        return randomRotation(np.random.default_rng(seed))
    if hasattr(orientation, 'toRotationMatrix'):
        return matrix(orientation)
    o = orientation
    if isinstance(o, (tuple, list)) and len(o) == 2 and np.size(o[0]) == 3:
        axis = np.asarray(o[0], dtype=float)
        n = np.linalg.norm(axis)
        if not n > 0:
            raise ValueError('orientation: rotation axis must be non-zero')
        a = float(o[1])
        return quaternionMatrix(np.concatenate([[math.cos(a / 2)], math.sin(a / 2) * axis / n]))
    a = np.asarray(o, dtype=float)
    if a.shape == (3, 3):
        if not (np.allclose(a.dot(a.T), np.eye(3), atol=1e-9) and np.linalg.det(a) > 0):
            raise ValueError('orientation: the matrix is not a rotation')
        return a
    if a.shape == (4,):
        if not np.linalg.norm(a) > 0:
            raise ValueError('orientation: zero quaternion')
        return quaternionMatrix(a)
    raise ValueError("orientation: give a Quaternion, (axis, angle), a 3x3 rotation matrix, (w, x, y, z) or 'random'")


def _quaternion(V, me):
    return me.Quaternion(me.Matrix3(*[float(V[i, j]) for i in range(3) for j in range(3)]))


class _Target(object):
    """What one clump is to get: members (YADE bodies), mass, centre of mass, tensor (world), unit-density ones."""

    def __init__(self, bodies, volume, centroid, inertia, density):
        self.bodies = bodies
        self.volume = float(volume)
        self.centroid = np.asarray(centroid, dtype=float)
        self.unitInertia = np.asarray(inertia, dtype=float)
        self.density = float(density)
        self.M = self.density * self.volume
        self.I = self.density * self.unitInertia


def _withLoads(targets, action, me):
    """Runs *action* (a YADE call that sums clump members) while the members of every target carry the loads
    that make the sums exact; then gives the spheres back, each with its share of the mass."""
    from yade.wrapper import Box
    tmp = Box(extents=me.Vector3(0, 0, 0))
    saved = []
    try:
        for t in targets:
            x = np.array([[b.state.pos[0], b.state.pos[1], b.state.pos[2]] for b in t.bodies])
            r = np.array([b.shape.radius for b in t.bodies])
            t.loads = memberLoads(x, r, t.M, t.centroid, t.I)
            for b, m in zip(t.bodies, t.loads.m):
                saved.append((b, b.shape))
                b.shape = tmp
                b.state.mass = float(m)
                b.state.inertia = me.Vector3(0, 0, 0)
            b0 = t.bodies[0]
            b0.state.inertia = me.Vector3(*[float(v) for v in t.loads.j])
            # YADE turns a member's tensor by ori.conjugate() (Clump::inertiaTensorRotate): V = matrix(ori*)
            b0.state.ori = _quaternion(t.loads.V, me).conjugate()
        return action()
    finally:
        for b, shape in saved:
            b.shape = shape
        for t in targets:
            if hasattr(t, 'loads'):
                for b, m in zip(t.bodies, t.loads.final):
                    b.state.mass = float(m)
                    b.state.inertia = me.Vector3(1, 1, 1) * float(0.4 * m * b.shape.radius ** 2)


def _check(O, cid, t):
    """The clump took the wanted properties (YADE chose the principal frame itself)."""
    st = O.bodies[cid].state
    C = t.loads.centroid
    size = max(1.0, float(np.abs(C).max()))
    ok = (abs(st.mass - t.M) <= 1e-9 * t.M and np.linalg.norm(np.array(st.pos) - C) <= 1e-9 * size
          and np.linalg.norm(stateTensor(st) - t.I) <= 1e-7 * np.linalg.norm(t.I))
    if not ok:
        raise RuntimeError('mssClump: YADE did not take the requested mass properties of clump %d (mass %g vs %g)'
                           % (cid, st.mass, t.M))


def _record(O, cid, t):
    """Keeps the clump's exact unit-density properties in O.tags, in its first member's frame (members turn
    with the clump, so the record stays valid whatever the clump does)."""
    b0 = t.bodies[0]
    R0 = matrix(b0.state.ori)
    p0 = np.array([b0.state.pos[0], b0.state.pos[1], b0.state.pos[2]])
    rec = {'members': [b.id for b in t.bodies], 'radii': [b.shape.radius for b in t.bodies],
           'volume': t.volume, 'centroid': R0.T.dot(t.loads.centroid - p0).tolist(),
           'inertia': R0.T.dot(t.unitInertia).dot(R0).ravel().tolist()}
    O.tags[TAG + str(cid)] = json.dumps(rec, separators=(',', ':'))


def _recorded(O, cid):
    try:
        return json.loads(O.tags[TAG + str(cid)])
    except (KeyError, ValueError):
        return None


def buildClump(centers, radii, volume, centroid, unitInertia, body, warn=None):
    """Appends one clump of spheres (*body*: keywords for ``utils.sphere``) with mass density x *volume*, centre
    *centroid* and tensor density x *unitInertia*; O.bodies is unchanged if anything fails.
    :return: (clumpId, [memberIds])"""
    utils, O, me = _yade()
    bodies = [utils.sphere(tuple(float(x) for x in p), float(r), **body) for p, r in zip(centers, radii)]
    density = bodies[0].material.density
    if not density > 0:
        raise ValueError('mssClump: the material density must be > 0, got %g' % density)
    t = _Target(bodies, volume, centroid, unitInertia, density)
    cid, ids = _withLoads([t], lambda: O.bodies.appendClumped(bodies, discretization=0), me)
    try:
        _check(O, cid, t)
    except RuntimeError:
        O.bodies.erase(cid, True)
        raise
    _record(O, cid, t)
    if t.loads.offset > 0 and warn is not None:
        warn(t.loads.offset)
    return cid, list(ids)


def _offsetWarning(offset):
    import warnings
    warnings.warn('mssClump: the centre of mass lies %.3g off the plane or line of the sphere centres; the clump '
                  'takes the nearest point of it (its mass and tensor are exact)' % offset)


def mssClump(source, center=None, orientation=None, scale=1.0, mass='target', seed=None, **options):
    """Builds one YADE clump from a grain and appends it to O.bodies, as ``O.bodies.appendClumped`` does.

    :param source: mesh file, voxel file (.npy), 3-D numpy array, (vertices, triangles), or an :class:`MssResult`
        (then no generation happens)
    :param options: every keyword of :func:`generate` (nSpheres, eta, dice, rMin, voxelSize, resolution,
        method, clip, planes, label, origin, supersample, threads, memoryLimit, ...) and of ``utils.sphere``
        for the bodies (material, color, mask, fixed, wire, highlight). An unknown keyword raises TypeError
        naming the closest valid one, before anything is generated.
    :param Vector3 center: where the clump's centre of mass goes (default: where it is in the file's frame)
    :param orientation: rotation about the centre of mass: a Quaternion, (axis, angle), a 3x3 matrix,
        (w, x, y, z), or 'random' (uniform over all rotations; *seed* makes it reproducible)
    :param float scale: size factor about the centre of mass
    :param str mass: 'target': mass, centre and inertia of the target solid (exact for a mesh; voxel sums);
        'union': those of the union of the spheres (overlaps counted once)
    :return: (clumpId, [memberIds]); O.bodies is unchanged if anything fails

    The clump's members are exactly the spheres; each carries its share of the clump's mass (``state.mass``,
    positive, adding up to the clump's). YADE's ``updateClumpProperties``, ``addToClump`` and
    ``releaseFromClump`` recompute a clump from its spheres as YADE always does (overlaps counted twice at
    discretization 0); :func:`restoreClumpProperties` gives the exact properties back.
    """
    gen, body = split('mssClump', options, GENERATE_OPTIONS, bodyOptions())
    utils, O, me = _yade()
    if mass not in ('target', 'union'):
        raise ValueError("mssClump: mass must be 'target' or 'union', got %r" % (mass,))
    if not (float(scale) > 0 and math.isfinite(float(scale))):
        raise ValueError('mssClump: scale must be > 0, got %r' % (scale,))
    R = rotation(orientation, seed)
    if center is not None:
        C = np.array([float(x) for x in center])
        if C.shape != (3,) or not np.all(np.isfinite(C)):
            raise ValueError('mssClump: center must be 3 finite numbers')
    if isinstance(source, MssResult):
        if gen:
            raise ValueError('mssClump: %s: generation options do nothing for an MssResult (already generated)'
                             % ', '.join(sorted(gen)))
        r = source
    else:
        r = generate(source, **gen)
    if mass == 'target':
        if r.targetMass is None:
            raise ValueError("mssClump: this result has no target solid (read from a sphere file?); use mass='union'")
        props = r.targetMass
    else:
        props = r.unionMass()
    C = props.centroid if center is None else C
    s = float(scale)
    placed = props.transformed(s, R, C)
    centers = C + (s * (r.centers - props.centroid)).dot(R.T)
    return buildClump(centers, s * r.radii, placed.volume, C, placed.inertia, body, _offsetWarning)


def _clumpIds(O):
    return [b.id for b in O.bodies if b is not None and b.isClump]


def restoreClumpProperties(clumpIds=None, resolution=200):
    """Gives clumps their exact mass properties back after YADE recomputed them from their spheres
    (``O.bodies.updateClumpProperties``, ``releaseFromClump``, ``addToClump``) or after a density change
    (the material's density is read now; members' masses follow).

    A clump from :func:`mssClump` (and friends) whose members are unchanged gets its grain's properties again
    (``mass='target'``: the grain's; ``'union'``: the union's), at the current density. A clump whose members
    changed, or any other clump of spheres named in *clumpIds*, gets those of the union of its spheres (overlaps
    counted once, *resolution* voxels along the longest edge), and is remembered so from then on. The clumps'
    velocities and angular momenta are kept (the centre of mass may move: its velocity follows).

    :param clumpIds: clump ids; default every clump made by yade_mss in the scene
    :return: list of (clumpId, 'grain' or 'union')
    """
    utils, O, me = _yade()
    if clumpIds is None:
        ids = sorted(int(k[len(TAG):]) for k in O.tags.keys() if k.startswith(TAG) and O.tags[k])
        explicit = False
    else:
        ids = [int(i) for i in clumpIds]
        explicit = True
    targets, kinds, done = [], [], []
    from yade.wrapper import Sphere
    for cid in ids:
        body = O.bodies[cid] if 0 <= cid < len(O.bodies) else None
        if body is None or not body.isClump:
            if explicit:
                raise ValueError('restoreClumpProperties: body %d is not a clump' % cid)
            O.tags[TAG + str(cid)] = ''  # the clump was erased: forget it (O.tags cannot delete a key)
            continue
        members = [O.bodies[i] for i in sorted(body.shape.members.keys())]
        for b in members:
            if not isinstance(b.shape, Sphere):
                raise ValueError('restoreClumpProperties: member %d of clump %d is a %s, not a Sphere'
                                 % (b.id, cid, type(b.shape).__name__))
        rec = _recorded(O, cid)
        radii = [b.shape.radius for b in members]
        if rec and sorted(rec['members']) == [b.id for b in members] and \
                np.allclose(sorted(rec['radii']), sorted(radii), rtol=1e-12, atol=0):
            byId = {b.id: b for b in members}
            members = [byId[i] for i in rec['members']]  # the recorded order: its first member is the frame
            b0 = members[0]
            R0 = matrix(b0.state.ori)
            p0 = np.array([b0.state.pos[0], b0.state.pos[1], b0.state.pos[2]])
            V = rec['volume']
            C = p0 + R0.dot(rec['centroid'])
            I = R0.dot(np.reshape(rec['inertia'], (3, 3))).dot(R0.T)
            kind = 'grain'
        else:
            x = [c for b in members for c in (b.state.pos[0], b.state.pos[1], b.state.pos[2])]
            u = _mss.massSpheres(x, radii, int(resolution))
            V, C, I = u['volume'], np.array(u['centroid']), np.reshape(u['inertia'], (3, 3))
            kind = 'union'
        density = members[0].material.density
        if not density > 0:
            raise ValueError('restoreClumpProperties: clump %d: the material density must be > 0, got %g'
                             % (cid, density))
        t = _Target(members, V, C, I, density)
        st = body.state
        t.cid = cid
        t.before = (np.array(st.pos), np.array(st.vel), np.array(st.angVel))
        targets.append(t)
        kinds.append(kind)
    if not targets:
        return done
    wanted = set(t.cid for t in targets)
    others = [i for i in _clumpIds(O) if i not in wanted]
    _withLoads(targets, lambda: O.bodies.updateClumpProperties(excludeList=others, discretization=0), me)
    for t, kind in zip(targets, kinds):
        _check(O, t.cid, t)
        st = O.bodies[t.cid].state
        pos0, vel0, w = t.before
        # YADE's update zeroes the velocities: keep the motion (the centre of mass may have moved)
        st.vel = me.Vector3(*(vel0 + np.cross(w, np.array(st.pos) - pos0)))
        st.angVel = me.Vector3(*w)
        st.angMom = me.Vector3(*stateTensor(st).dot(w))
        _record(O, t.cid, t)
        done.append((t.cid, kind))
    return done
