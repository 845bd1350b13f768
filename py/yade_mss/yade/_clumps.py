"""YADE clumps whose members are YADE's own spheres and whose clump body has the mass properties asked for.

How (YADE 2023.02a, stock, through its Python API; see :mod:`yade_mss._loads` for the sums): while YADE sums
the members (``appendClumped``, ``updateClumpProperties``), each member wears a temporary non-spherical shape
(a zero-size ``Box``) and carries a mass chosen for it, one member also a tensor and an orientation, so that
YADE's own sums give the wanted mass, centre of mass and inertia tensor, and YADE itself places the clump in the
principal frame and records the members' relative positions. Then every member becomes the sphere
``utils.sphere`` makes: its ``Sphere`` shape, mass rho V and inertia 2/5 m r^2 of its material, exactly as after
``O.bodies.appendClumped``. YADE reads member masses (contact laws such as ``Ip2_ViscElMat_ViscElMat_ViscElPhys``,
``utils.PWaveTimeStep``, spheres freed by ``releaseFromClump`` or ``erase``), so members must be YADE's; only the
clump body carries the exact properties, and nothing recomputes them on steps, ``O.save``/``O.load`` or
``loadTmp``. ``updateClumpProperties``, ``addToClump`` and ``releaseFromClump`` sum the spheres as YADE always
does (overlaps counted twice); :func:`restoreClumpProperties` gives the exact properties back.

As for any YADE clump, ``utils.getSpheresMass()`` sums the members (overlapping volume counted twice); the
mass of the grains is the clumps' (:func:`totalMass`).

Why not an extra member: a correction body (tried first) breaks YADE's clump API (release, erase, exporters).
Why not a C++ extension against YADE's headers: Debian ships none, and a fork's headers tie the package to
Debian's binary layout.

Each clump's exact properties (unit density, in the frame of its second member) are carried by the clump body
itself, as the label of a material of its own (YADE's clumps have none; :mod:`yade_mss._records`): YADE saves
them with the body, and they go with it. A fingerprint of the members (their ids, radii and positions in that
frame) is checked before they are applied.
"""

import inspect
import json
import math
import os
import random
import warnings

import numpy as np

from ..base import INT64_MAX, flag, integer, number, quaternionMatrix, randomRotation, split, vector3
from ..grains import GENERATE_OPTIONS, VOLUME_EXT, Mesh, MssResult, generate, readGrain
from ._loads import memberLoads
from ._records import attach, encodeGrain, encodeParts, recordParts
from ._stiffness import checkStiffness, grainMaterial

_colours = random.Random()  # utils.randomColor's uniform colours, without reseeding the user's `random`


def yadeModules():
    try:
        from yade import utils
        from yade.wrapper import Omega
        import yade.minieigenHP as me
    except ImportError:
        raise RuntimeError('this function builds YADE bodies: run the script with yade (yade -n -x script.py)')
    return utils, Omega(), me


_bodyOptions = []


def bodyOptions():
    """The body keywords of ``utils.sphere`` (material, color, mask, fixed, wire, highlight, ...), and
    contactStiffness ('spheres': YADE's own; 'grain': one contact of the grains, whatever the sphere count, see
    :func:`contactStiffnessEngine`)."""
    if not _bodyOptions:
        utils, O, me = yadeModules()
        _bodyOptions.extend(p for p in inspect.signature(utils.sphere).parameters if p not in ('center', 'radius'))
        _bodyOptions.append('contactStiffness')
    return tuple(_bodyOptions)


def matrix(q):
    """3x3 numpy rotation matrix of a YADE Quaternion."""
    m = q.toRotationMatrix()
    return np.array([[m[i, j] for j in range(3)] for i in range(3)])


def stateTensor(state):
    """Inertia tensor (world axes, about the centre of mass) of a YADE State."""
    R = matrix(state.ori)
    return R.dot(np.diag([state.inertia[0], state.inertia[1], state.inertia[2]])).dot(R.T)


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
        axis = vector3('orientation', 'orientation (its axis)', o[0])
        n = np.linalg.norm(axis)
        if not n > 0:
            raise ValueError('orientation: rotation axis must be non-zero')
        a = number('orientation', 'orientation (its angle)', o[1])
        return quaternionMatrix(np.concatenate([[math.cos(a / 2)], math.sin(a / 2) * axis / n]))
    try:
        a = np.asarray(o, dtype=float)
    except (TypeError, ValueError):
        raise TypeError("orientation: give a Quaternion, (axis, angle), a 3x3 rotation matrix, (w, x, y, z) or "
                        "'random', got %r" % (o,))
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


def _finite(func, name, value, positive=False):
    v = number(func, name, value)
    if positive and not v > 0:
        raise ValueError('%s: %s must be a finite number > 0, got %r' % (func, name, value))
    return v


def _checkBody(func, body):
    """The types utils.sphere's keywords must have, checked before YADE sees them (YADE's own errors for these
    are Boost's signatures or a member silently wrong)."""
    for key in ('fixed', 'wire', 'highlight'):
        if key in body and not isinstance(body[key], (bool, np.bool_)):
            raise TypeError('%s: %s must be True or False, got %r' % (func, key, body[key]))
    if body.get('dynamic') is not None and not isinstance(body['dynamic'], (bool, np.bool_)):
        raise TypeError('%s: dynamic must be True, False or None, got %r' % (func, body['dynamic']))
    if 'mask' in body:
        body['mask'] = integer(func, 'mask', body['mask'])
    if body.get('color') is not None:
        c = vector3(func, 'color', body['color'])
        if not np.all((c >= 0) & (c <= 1)):
            raise ValueError('%s: color components must be in [0, 1], got %r' % (func, body['color']))
        body['color'] = tuple(float(v) for v in c)
    if 'material' in body:
        m = body['material']
        if isinstance(m, (bool, np.bool_)) or isinstance(m, float):
            raise TypeError('%s: material must be a Material, a label, an index into O.materials or a factory, '
                            'got %r' % (func, m))
    return body


class _Members(object):
    """Makes members exactly as ``utils.sphere(center, radius, **body)`` does: the options are checked by a first
    sphere that utils.sphere itself makes, whose material, blocked DOFs, mask, bound flag and shape flags every
    member then takes (utils.sphere reseeds Python's ``random`` for each colour: most of its time)."""

    def __init__(self, func, body):
        utils, O, me = yadeModules()
        from yade.wrapper import Body, Sphere
        self.utils, self.me, self.Body, self.Sphere = utils, me, Body, Sphere
        self.func = func
        self.body = _checkBody(func, dict(body))
        stiffness = checkStiffness(func, self.body.pop('contactStiffness', 'spheres'))
        m = self.body.get('material')
        self.factory = m is not None and callable(m) and not isinstance(m, (int, str))
        try:  # with a colour: utils.sphere would reseed Python's random for a random one
            proto = utils.sphere((0.0, 0.0, 0.0), 1.0, **dict(self.body, color=self.body.get('color') or (1, 1, 1)))
        except Exception as e:
            raise ValueError('%s: utils.sphere refused the body options %s: %s' % (
                func, ', '.join('%s=%r' % kv for kv in sorted(self.body.items())) or '(none)', e))
        self.mat = proto.mat
        if stiffness == 'grain':  # the members' material says so (_stiffness.py): a twin of the material
            if self.factory:
                raise ValueError("%s: contactStiffness='grain' needs a material, not a factory of them" % func)
            self.mat = self.body['material'] = grainMaterial(self.mat)
        self.blocked = proto.state.blockedDOFs
        self.mask = proto.mask
        self.bounded = proto.bounded
        self.wire, self.highlight = proto.shape.wire, proto.shape.highlight
        c = self.body.get('color')
        self.color = me.Vector3(*c) if c else None
        if not self.factory:
            self.density(self.mat)

    def density(self, mat):
        rho = mat.density
        if not rho > 0:
            raise ValueError('%s: the material density must be > 0, got %g' % (self.func, rho))
        return rho

    def make(self, centers, radii):
        """The members: bodies, their masses and inertias (Vector3)."""
        V3 = self.me.Vector3
        if self.factory:
            bodies = [self.utils.sphere(tuple(float(v) for v in p), float(r), **self.body)
                      for p, r in zip(centers, radii)]
            return bodies, [b.state.mass for b in bodies], [b.state.inertia for b in bodies]
        bodies, masses, inertias = [], [], []
        mat, Body, Sphere = self.mat, self.Body, self.Sphere
        rho = mat.density
        for p, r in zip(centers.tolist(), radii.tolist()):
            b = Body()
            colour = self.color if self.color is not None else V3(_colours.random(), _colours.random(),
                                                                   _colours.random())
            b.shape = Sphere(radius=r, color=colour, wire=self.wire, highlight=self.highlight)
            b.mat = mat
            st = b.state = mat.newAssocState()
            st.pos = st.refPos = V3(*p)
            m, I = _sphereMass(r, rho, V3)
            st.mass, st.inertia = m, I
            b.bounded = self.bounded
            st.blockedDOFs = self.blocked
            b.aspherical = False
            b.mask = self.mask
            bodies.append(b)
            masses.append(m)
            inertias.append(I)
        return bodies, masses, inertias


class _Plan(object):
    """One clump at unit density: its members (centres, radii), the wanted volume, centre of mass and tensor,
    and the loads that make YADE's sums give them (:func:`yade_mss._loads.memberLoads`: masses *m*, member 0's
    tensor, eigenvalues *j* with eigenvectors *V*)."""
    __slots__ = ('centers', 'radii', 'volume', 'centroid', 'inertia', 'moments', 'm', 'j', 'V', 'offset', 'frame',
                 'base', 'parts')

    def __init__(self):
        # frame: (c0, s, R, C) of a placement; base: the plan it was placed from; parts: the record parts a base
        # plan keeps per placement (a placed plan keeps none)
        self.frame = self.base = self.parts = None

    @staticmethod
    def of(centers, radii, volume, centroid, inertia):
        p = _Plan()
        p.centers = np.asarray(centers, dtype=float).reshape(-1, 3)
        p.radii = np.asarray(radii, dtype=float).reshape(-1)
        p.inertia = np.asarray(inertia, dtype=float).reshape(3, 3)
        L = memberLoads(p.centers, p.radii, float(volume), centroid, p.inertia)
        p.volume, p.centroid, p.offset = float(volume), L.centroid, L.offset
        p.moments = np.linalg.eigvalsh(p.inertia)
        p.m, p.j, p.V = L.m, L.j, L.V
        p.parts = {}
        return p

    def world(self, points):
        """Points (n, 3) of the plan's own frame (its result's) where this placement puts them."""
        if self.frame is None:
            return np.asarray(points, dtype=float)
        c0, s, R, C = self.frame
        return C + s * (np.asarray(points, dtype=float) - c0).dot(R.T)

    def partsKey(self):
        """Where this plan's record parts (:func:`yade_mss._records.recordParts`) are kept: (the plan it was placed
        from, key), or None. Placements with the same turn and scale share them; the frame is the identity for two
        members or more (member 1 wears YADE's), member 0's own axes for one."""
        if self.base is None or self.base.parts is None or len(self.radii) < 2:
            return None
        c0, s, R, C = self.frame
        return self.base, (float(s), np.asarray(R, dtype=float).tobytes())

    def placed(self, c0, s, R, C):
        """This plan moved so that its point *c0* goes to *C*, turned by *R* and scaled by *s* about it: the
        loads are equivariant (masses ~ s^3, tensors ~ s^5 and turned), so nothing is solved again."""
        q = _Plan()
        q.centers = C + s * (self.centers - c0).dot(R.T)
        q.radii = s * self.radii
        q.volume = s ** 3 * self.volume
        q.centroid = C + s * R.dot(self.centroid - c0)
        q.inertia = s ** 5 * R.dot(self.inertia).dot(R.T)
        q.moments = s ** 5 * self.moments
        q.m, q.j, q.V, q.offset = s ** 3 * self.m, s ** 5 * self.j, R.dot(self.V), s * self.offset
        q.frame = (c0, s, R, C)
        q.base = self
        return q

    def placedMany(self, c0, s, R, C):
        """:meth:`placed` for k placements at once: rotations *R* (k, 3, 3), centres *C* (k, 3), one scale."""
        centers = C[:, None, :] + s * np.einsum('kij,nj->kni', R, self.centers - c0)
        centroid = C + s * np.einsum('kij,j->ki', R, self.centroid - c0)
        inertia = s ** 5 * np.einsum('kij,jl,kml->kim', R, self.inertia, R)
        V = np.einsum('kij,jl->kil', R, self.V)
        out = []
        for k in range(len(R)):
            q = _Plan()
            q.centers, q.radii, q.volume, q.centroid, q.inertia = centers[k], s * self.radii, s ** 3 * self.volume, \
                centroid[k], inertia[k]
            q.moments, q.m, q.j, q.V, q.offset = s ** 5 * self.moments, s ** 3 * self.m, s ** 5 * self.j, V[k], \
                s * self.offset
            q.frame = (c0, s, R[k], C[k])
            q.base = self
            out.append(q)
        return out


def _basePlan(r, mass):
    """The plan of result *r* in its own frame for *mass* ('target' or 'union'), kept with the result (so a
    template's clumps reuse it) and remade when its spheres change. :return: (plan, the target's centroid)"""
    key = (mass, r.centers.tobytes(), r.radii.tobytes())
    cached = getattr(r, '_mssPlan', None)
    if cached is not None and cached[0] == key:
        return cached[1], cached[2]
    props = r.targetMass if mass == 'target' else r.unionMass()
    plan = _Plan.of(r.centers, r.radii, props.volume, props.centroid, props.inertia)
    r._mssPlan = (key, plan, np.asarray(props.centroid, dtype=float))
    return plan, r._mssPlan[2]


def _sphereMass(radius, density, V3):
    """(mass, inertia) of ``utils.sphere``: the same floating-point operations, so the same bits."""
    V = (4. / 3) * math.pi * radius ** 3
    g = (2. / 5.) * V * radius ** 2 * density
    return V * density, V3(g, g, g)


def _withLoads(groups, action, me):
    """Runs *action* (a YADE call that sums clump members) while the members of every group carry the loads
    that make the sums exact; then every member is YADE's sphere again.

    A group: (bodies, masses for the sums, final masses, final inertias (Vector3), whether to set the members'
    inertias first, member 0's moments *j* and axes *V*, and the members' (shape, state) as already read, or
    None). Through the sums every member keeps its final sphere inertia (isotropic: its orientation does not
    matter), so member 0's tensor is *j* less the others'; the inertias are set first only where they may not
    be the final ones already (after a density change)."""
    from yade.wrapper import Box
    tmp = Box(extents=me.Vector3(0, 0, 0))
    done = []
    try:
        for bodies, m, final, inertia, setInertia, j, V, refs in groups:
            if refs is None:
                refs = [(b.shape, b.state) for b in bodies]
            done.append((bodies, refs, final, inertia))
            for b, (shape, st), mi in zip(bodies, refs, m):
                b.shape = tmp
                st.mass = mi
            if setInertia:
                for (shape, st), Ii in zip(refs, inertia):
                    st.inertia = Ii
            rest = sum(Ii[0] for Ii in inertia[1:])
            b0 = refs[0][1]
            b0.inertia = me.Vector3(*(j - rest).tolist())
            # YADE turns a member's tensor by ori.conjugate() (Clump::inertiaTensorRotate): V = matrix(ori*)
            b0.ori = _quaternion(V, me).conjugate()
        return action()
    finally:
        for bodies, refs, final, inertia in done:
            for b, (shape, st), mf in zip(bodies, refs, final):
                b.shape = shape
                st.mass = mf
            refs[0][1].inertia = inertia[0]


def _check(func, O, cid, M, C, moments):
    """The clump took the wanted mass, centre and principal moments (YADE chose the principal frame itself):
    :func:`_checkMany` for one clump."""
    _checkMany(func, [cid], [O.bodies[cid].state], np.array([M], dtype=float), np.array([C], dtype=float),
               np.array([moments], dtype=float))


def _checkMany(func, cids, states, M, C, moments):
    """Each clump took the wanted mass, centre and principal moments: their states (already read), wanted masses
    (k), centres (k, 3) and ascending principal moments (k, 3). YADE sums the members' tensors about the world's
    origin and then moves the sum to the centre of mass, which loses about eps M |C|^2 (a grain far from the
    origin for its size): the tolerance allows for it."""
    # clump by clump in plain floats: most calls check one clump, where numpy's overhead was most of the cost
    for k, st in enumerate(states):
        m, p, inertia = st.mass, st.pos, st.inertia
        got = sorted((inertia[0], inertia[1], inertia[2]))
        want, Mk = [float(x) for x in moments[k]], float(M[k])
        cx, cy, cz = (float(x) for x in C[k])
        size = max(1.0, abs(cx), abs(cy), abs(cz))
        far = 100 * 2.2e-16 * Mk * (cx * cx + cy * cy + cz * cz)
        if (abs(m - Mk) > 1e-9 * Mk or math.sqrt((p[0] - cx) ** 2 + (p[1] - cy) ** 2 + (p[2] - cz) ** 2) > 1e-9 * size
                or max(abs(g - w) for g, w in zip(got, want)) > 1e-7 * max(want) + far):
            raise RuntimeError('%s: YADE did not take the requested mass properties of clump %d (mass %g vs %g, '
                               'principal moments %s vs %s)' % (func, cids[k], m, Mk, got, want))


def _build(func, plans, members, warn=None, grains=None):
    """Appends one clump per plan, members made by *members* (:class:`_Members`); nothing is left in O.bodies
    if anything fails. *grains*: per plan, the grain's mesh (world vertices (n, 3), triangles) for a clump that
    can break (:func:`yade_mss.mssSplit`) or that mesh already encoded in the record's frame
    (:func:`yade_mss._records.encodeGrain`), or None. :return: [(clumpId, [memberIds])]"""
    utils, O, me = yadeModules()
    made = []
    try:
        for p in plans:
            # built about the world's origin, then moved where it goes: YADE sums the members' tensors about the
            # origin and moves the sum to the centre, which cost eps M |C|^2 (a split piece 1.2 km from the origin
            # took its inertia 5e-7 off)
            shift = np.asarray(p.centroid, dtype=float)
            bodies, final, inertia = members.make(p.centers - shift, p.radii)
            rho = members.density(bodies[0].mat)
            cid, ids = _withLoads([(bodies, (rho * p.m).tolist(), final, inertia, False, rho * p.j, p.V, None)],
                                  lambda: O.bodies.appendClumped(bodies, discretization=0), me)
            ids = list(ids)
            made.append((cid, ids))
            _check(func, O, cid, rho * p.volume, np.zeros(3), (rho * p.moments).tolist())
            if np.any(shift):
                by = me.Vector3(*shift.tolist())
                for i in [cid] + ids:
                    st = O.bodies[i].state
                    st.pos, st.refPos = st.pos + by, st.refPos + by
            if members.blocked:  # fixed=True (or dynamic=False) means the clump: members are never integrated
                O.bodies[cid].state.blockedDOFs = members.blocked
            if p.offset > 0 and warn is not None:
                warn(func, p.offset)
        # member 0 wears V* (above), the others YADE's identity orientation
        texts = encodeParts([ids for cid, ids in made], _recordParts(plans))
        from yade.wrapper import Material
        for k, ((cid, ids), text) in enumerate(zip(made, texts)):
            g = grains[k] if grains is not None else None
            # in the record's frame: member 0's position, member 1's orientation (the identity: YADE's); a text
            # is a grain encoded so already
            attach(O.bodies[cid], text, Material, '' if g is None or len(ids) < 2 else g if isinstance(g, str)
                   else encodeGrain(g[0] - plans[k].centers[0], g[1]))
    except Exception:
        for cid, ids in made:
            O.bodies.erase(cid, True)
        raise
    return made


_PARTS_KEPT = 16  # placements remembered per plan: a cloud's random turns never repeat


def _recordParts(plans):
    """Each plan's :func:`yade_mss._records.recordParts`, computed together for those not placed alike before (the
    numpy work of a record was an eighth of an mssClump)."""
    parts, todo = [None] * len(plans), []
    for k, p in enumerate(plans):
        key = p.partsKey()
        parts[k] = key[0].parts.get(key[1]) if key is not None else None
        if parts[k] is None:
            todo.append(k)
    if todo:
        sub = [plans[k] for k in todo]
        made = recordParts([p.centers for p in sub], [p.radii for p in sub], np.array([p.volume for p in sub]),
                           np.array([p.centroid for p in sub]), np.array([p.inertia for p in sub]), [p.m for p in sub],
                           np.array([p.V for p in sub]), np.array([p.j for p in sub]),
                           np.array([np.eye(3) if len(p.radii) > 1 else p.V.T for p in sub]))
        for k, part in zip(todo, made):
            parts[k] = part
            key = plans[k].partsKey()
            if key is not None and len(key[0].parts) < _PARTS_KEPT:
                key[0].parts[key[1]] = part
    return parts


def buildClump(centers, radii, volume, centroid, unitInertia, body, warn=None, func='mssClump'):
    """Appends one clump of spheres (*body*: keywords for ``utils.sphere``) with mass density x *volume*, centre
    *centroid* and tensor density x *unitInertia*; O.bodies is unchanged if anything fails.
    :return: (clumpId, [memberIds])"""
    plan = _Plan.of(centers, radii, volume, centroid, unitInertia)
    return _build(func, [plan], _Members(func, body), warn)[0]


def _offsetWarning(func, offset):
    warnings.warn('%s: the centre of mass lies %.3g off the plane or line of the sphere centres; the clump '
                  'takes the nearest point of it (its mass and tensor are exact)' % (func, offset), stacklevel=3)


def _scale(func, scale):
    return _finite(func, 'scale', scale, positive=True)


def _mass(func, mass):
    if mass not in ('target', 'union'):
        raise ValueError("%s: mass must be 'target' or 'union', got %r" % (func, mass))
    return mass


def _seed(func, seed):
    return None if seed is None else integer(func, 'seed', seed, None, INT64_MAX)


def _plans(func, r, mass, placements):
    """Plans of result *r* placed at (center or None, rotation matrix, scale): the target's (or the union's)
    centre of mass goes to *center* (None: where it is)."""
    if mass == 'target' and r.targetMass is None:
        raise ValueError("%s: this result has no target solid (read from a sphere file?); use mass='union'" % func)
    base, c0 = _basePlan(r, mass)
    return [base.placed(c0, s, R, c0 if C is None else C) for C, R, s in placements]


def grainMesh(func, r):
    """The mesh (vertices (n, 3), triangles (m, 3)) result *r* was generated from, for a breakable clump."""
    cached = getattr(r, '_mssMesh', None)
    if cached is not None:
        return cached
    g = r.grain
    s = readGrain(g) if g is not None and not isinstance(g, np.ndarray) else None
    if not isinstance(s, Mesh):
        raise ValueError('%s: breakable=True needs the grain as a mesh (a mesh file or (vertices, triangles)); '
                         'this result was made from %s' % (func, 'voxels' if s is not None or g is not None
                                                            else 'nothing it knows (read from a file?)'))
    if len(r.radii) < 2:  # a lone member's record frame is its own orientation, which restores rewrite
        raise ValueError('%s: breakable=True needs two spheres or more, this result has %d' % (func, len(r.radii)))
    r._mssMesh = (s.vertices, s.triangles)
    return r._mssMesh


def grainsOf(func, results, plans, breakable):
    """Each plan's grain in the world (:func:`_build`'s *grains*; plan k made from result results[k]), or None
    when not *breakable*."""
    if not flag(func, 'breakable', breakable):
        return None
    meshes = {}
    for r in results:
        if id(r) not in meshes:
            meshes[id(r)] = grainMesh(func, r)
    return [(p.world(meshes[id(r)][0]), meshes[id(r)][1]) for r, p in zip(results, plans)]


def mssClump(source, center=None, orientation=None, scale=1.0, mass='target', seed=None, breakable=False,
             **options):
    """Builds one YADE clump from a grain and appends it to O.bodies, as ``O.bodies.appendClumped`` does.

    :param source: mesh file, voxel file (.npy, .tif), 3-D numpy array, (vertices, triangles), or an
        :class:`MssResult` (then no generation happens)
    :param options: every keyword of :func:`generate` (nSpheres, eta, dice, rMin, voxelSize, resolution,
        method, clip, planes, label, origin, supersample, threads, memoryLimit, ...) and of ``utils.sphere``
        for the bodies (material, color, mask, fixed, wire, highlight), and contactStiffness: 'spheres'
        (YADE's own, the default) or 'grain' (a pair of clumps as stiff as one contact of their grains, whatever
        the sphere count; put :func:`contactStiffnessEngine` in O.engines). An unknown keyword raises TypeError
        naming the closest valid one, before anything is generated.
    :param Vector3 center: where the clump's centre of mass goes (default: where it is in the file's frame)
    :param orientation: rotation about the centre of mass: a Quaternion, (axis, angle), a 3x3 matrix,
        (w, x, y, z), or 'random' (uniform over all rotations; *seed* makes it reproducible)
    :param float scale: size factor about the centre of mass
    :param str mass: 'target': mass, centre and inertia of the target solid (exact for a mesh; voxel sums);
        'union': those of the union of the spheres (overlaps counted once)
    :param int seed: seed of ``orientation='random'``
    :param bool breakable: the clump carries its grain's mesh, so that :func:`mssSplit` (and
        :func:`MssBreakage`) can break it (a mesh source; at least two spheres)
    :return: (clumpId, [memberIds]); O.bodies is unchanged if anything fails

    The members are YADE's spheres, as after ``appendClumped``: mass rho V and inertia 2/5 m r^2 of their
    material, so contact laws and time steps that read them see what they see for any YADE clump. Only the
    clump body carries the exact properties. ``fixed=True`` (or ``dynamic=False``) fixes the clump. YADE's
    ``updateClumpProperties``, ``addToClump`` and ``releaseFromClump`` recompute a clump from its spheres as
    YADE always does (overlaps counted twice at discretization 0); :func:`restoreClumpProperties` gives the
    exact properties back.
    """
    gen, body = split('mssClump', options, GENERATE_OPTIONS, bodyOptions(),
                      extra=('source', 'center', 'orientation', 'scale', 'mass', 'seed', 'breakable'))
    utils, O, me = yadeModules()
    mass = _mass('mssClump', mass)
    breakable = flag('mssClump', 'breakable', breakable)
    s = _scale('mssClump', scale)
    R = rotation(orientation, _seed('mssClump', seed))
    C = None if center is None else vector3('mssClump', 'center', center)
    members = _Members('mssClump', body)
    if isinstance(source, MssResult):
        if gen:
            raise ValueError('mssClump: %s: generation options do nothing for an MssResult (already generated)'
                             % ', '.join(sorted(gen)))
        r = source
    else:
        requireVoxelSize('mssClump', source, gen)
        r = generate(source, **gen)
    plans = _plans('mssClump', r, mass, [(C, R, s)])
    return _build('mssClump', plans, members, _offsetWarning, grainsOf('mssClump', [r], plans, breakable))[0]


def requireVoxelSize(func, source, gen):
    """Inside YADE, lengths are metres: a voxel volume (an array, or a .npy or .tif file) without its voxel edge
    would be taken as 1 m a voxel (a sand grain of 3e9 kg, without a word), so it is refused, saying how to
    give it."""
    path = os.fspath(source) if isinstance(source, (str, os.PathLike)) else None
    volume = isinstance(source, np.ndarray) or (path is not None and os.path.splitext(path)[1].lower() in VOLUME_EXT)
    if volume and gen.get('voxelSize') is None:
        raise ValueError('%s: %s is a voxel volume: give its voxel edge in metres, voxelSize=1.25e-5 for 12.5 um '
                         'voxels (--voxel-size on the command line; YADE\'s lengths are metres: without it a voxel '
                         'would be 1 m)' % (func, path if path is not None else 'the array'))


def clumpIdList(func, clumpIds, O, existing=True):
    """*clumpIds* as a list of ints: None is every clump of the scene; otherwise a list (tuple, array) of integers
    (numpy's too), each a clump of the scene with *existing* (a scalar, a string, a bool or a body that is not a
    clump is refused by name)."""
    if clumpIds is None:
        return _clumpIds(O)
    if isinstance(clumpIds, (str, bytes)) or not hasattr(clumpIds, '__iter__'):
        raise TypeError('%s: clumpIds must be a list of clump ids, got %r' % (func, clumpIds))
    ids = list(clumpIds)
    for i in ids:
        if isinstance(i, (bool, np.bool_)) or not isinstance(i, (int, np.integer)):
            raise TypeError('%s: clump ids must be integers, got %r' % (func, i))
    ids = [int(i) for i in ids]
    if existing:
        for cid in ids:
            body = O.bodies[cid] if 0 <= cid < len(O.bodies) else None
            if body is None or not body.isClump:
                raise ValueError('%s: body %d is not a clump' % (func, cid))
    return ids


def _clumpIds(O):
    return [b.id for b in O.bodies if b is not None and b.isClump]


def totalMass():
    """The mass of the scene as it moves: every body that is not a clump member, so each clump once with its
    own mass, plus free spheres, walls and facets with theirs. ``utils.getSpheresMass()`` instead sums every
    sphere, clump members included: for any YADE clump, ours or ``appendClumped``'s, overlapping volume is
    counted twice there."""
    utils, O, me = yadeModules()
    return float(sum(b.state.mass for b in O.bodies if b is not None and not b.isClumpMember))


SCAN_BOX_TAG = 'mss.scanBox'  # O.tags: the world box of the scan mssAssembly built the specimen from, JSON


def porosity(volume=None):
    """The porosity of a specimen of clumps from the grains' exact volumes: one minus the solid volume over
    *volume*. A clump counts its own mass over its members' density (for an mss clump the grain's exact volume;
    for ``appendClumped``'s, YADE's sum of its members), a free sphere its ball. ``utils.porosity()`` instead
    sums every sphere, members included: where members overlap (every clump) it counts that volume twice and
    goes negative in a dense packing.

    :param float volume: the container's volume (world units^3); default: the periodic cell's; for a specimen
        :func:`mssAssembly` built from a scan, the scan's box (the volume its voxels fill, as the scan's porosity
        is counted); else the box that holds every sphere
    :return: float
    """
    utils, O, me = yadeModules()
    solid = 0.0
    lo, hi = np.full(3, np.inf), np.full(3, -np.inf)
    for b in O.bodies:
        if b is None:
            continue
        if b.isClump:
            ids = list(b.shape.members.keys())
            if ids:
                solid += b.state.mass / O.bodies[ids[0]].material.density
        elif type(b.shape).__name__ == 'Sphere':
            r = b.shape.radius
            p = np.array([b.state.pos[0], b.state.pos[1], b.state.pos[2]])
            lo, hi = np.minimum(lo, p - r), np.maximum(hi, p + r)
            if not b.isClumpMember:
                solid += 4.0 / 3.0 * math.pi * r ** 3
    if volume is None:
        if O.periodic:
            volume = O.cell.volume
        elif SCAN_BOX_TAG in O.tags.keys():
            box = np.array(json.loads(O.tags[SCAN_BOX_TAG]), dtype=float)
            volume = float(np.prod(box[1] - box[0]))
        elif np.all(hi >= lo):
            volume = float(np.prod(hi - lo))
        else:
            raise ValueError('porosity: no sphere in the scene and no volume given')
    volume = number('porosity', 'volume', volume, 0.0)
    if volume <= 0:
        raise ValueError('porosity: volume must be > 0, got %r' % volume)
    return 1.0 - solid / volume
