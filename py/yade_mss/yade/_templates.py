"""Clump templates and packings: :class:`MssTemplate`, :func:`mssTemplate`, :func:`mssClumpCloud`,
:func:`mssReplaceByClumps`. Every clump is built by :func:`mssClump`: exact mass properties."""

import math
import warnings

import numpy as np

from ..base import INT64_MAX, flag as _flag, integer, randomRotation, split, vector3
from ..grains import GENERATE_OPTIONS, MssResult, generate
from ._clumps import (_Members, _basePlan, _build, _mass, _offsetWarning, _plans, _scale, _seed, bodyOptions, grainsOf,
                      requireVoxelSize, yadeModules)


class MssTemplate(object):
    """A grain as a clump template, generated once and reused for a packing (:func:`mssTemplate` makes one).

    :param result: the :class:`MssResult` of the grain
    :param float scale: the size factor applied to the result's units

    :ivar result: the :class:`MssResult`
    :ivar scale: the size factor applied to the file's units
    :ivar equivalentRadius: radius of the sphere of the grain's volume (the union's without a target), scaled
    :ivar boundingRadius: radius of the smallest ball about the union's centre of mass that holds every sphere,
        scaled: the distance two of these clumps need between their centres never to overlap
    :ivar clumpTemplate: ``utils.clumpTemplate`` for ``O.bodies.replaceByClumps`` (relative to the bounding
        radius; YADE scales it to the volume of the sphere it replaces, see :func:`mssReplaceByClumps`)
    :ivar spherePack: ``SpherePack`` for ``SpherePack.makeClumpCloud`` (file units times scale, centred at the
        union's centre of mass)
    """

    def __init__(self, result, scale=1.0):
        utils, O, me = yadeModules()
        from yade import pack
        self.result = result
        self.scale = float(scale)
        u = result.unionMass()
        volume = result.targetMass.volume if result.targetMass is not None else u.volume
        self.equivalentRadius = self.scale * (3.0 * volume / (4.0 * math.pi)) ** (1.0 / 3.0)
        self.unionCentroid = u.centroid
        rb = result.boundingRadius(u.centroid)
        self.boundingRadius = self.scale * rb
        rel = (result.centers - u.centroid) / rb
        self.clumpTemplate = utils.clumpTemplate(relRadii=[float(x) for x in result.radii / rb],
                                                 relPositions=[[float(x) for x in p] for p in rel])
        self.spherePackCenters = self.scale * (result.centers - u.centroid)
        self.spherePackRadii = self.scale * result.radii
        self.spherePack = pack.SpherePack([(tuple(float(x) for x in p), float(rad))
                                           for p, rad in zip(self.spherePackCenters, self.spherePackRadii)])

    def __repr__(self):
        return '<MssTemplate %d spheres, equivalent radius %.4g, bounding radius %.4g>' % (
            len(self.result), self.equivalentRadius, self.boundingRadius)

    def plan(self, center, rotation, scale=1.0, mass='target'):
        """The plan of this grain as a clump (what :meth:`place` builds), without building it.

        :param center: where the union's centre of mass (the template's origin) goes, 3 numbers
        :param rotation: 3x3 rotation matrix (numpy)
        :param float scale: a size factor on top of the template's scale
        :param str mass: 'target' (the grain's mass properties) or 'union' (the spheres' union's)
        """
        t = self.result
        mass = mass if t.targetMass is not None else 'union'
        props = t.targetMass if mass == 'target' else t.unionMass()
        s = self.scale * scale
        c = np.asarray(center, dtype=float) + s * rotation.dot(props.centroid - self.unionCentroid)
        return _plans('MssTemplate.place', t, mass, [(c, rotation, s)])[0]

    def plans(self, centers, rotations, mass='target'):
        """:meth:`plan` for k placements at once, at the template's scale.

        :param centers: (k, 3) numpy array
        :param rotations: (k, 3, 3) numpy array of rotation matrices
        :param str mass: 'target' or 'union', as in :meth:`plan`
        """
        t = self.result
        mass = mass if t.targetMass is not None else 'union'
        props = t.targetMass if mass == 'target' else t.unionMass()
        s = self.scale
        C = np.asarray(centers, dtype=float) + s * np.einsum('kij,j->ki', rotations, props.centroid - self.unionCentroid)
        if mass == 'target' and t.targetMass is None:
            raise ValueError("MssTemplate.plans: this result has no target solid; use mass='union'")
        base, c0 = _basePlan(t, mass)
        return base.placedMany(c0, s, np.asarray(rotations, dtype=float), C)

    def place(self, center, rotation, scale=1.0, mass='target', **body):
        """Builds this grain as a clump in the scene.

        :param center: where the union's centre of mass goes, 3 numbers
        :param rotation: 3x3 rotation matrix (numpy)
        :param float scale: a size factor on top of the template's scale
        :param str mass: 'target' or 'union', as in :meth:`plan`
        :param body: ``utils.sphere`` keywords (material, color, mask, fixed, ...)
        :return: (clumpId, [memberIds])
        """
        return _build('MssTemplate.place', [self.plan(center, rotation, scale, _mass('MssTemplate.place', mass))],
                      _Members('MssTemplate.place', body), _offsetWarning)[0]


def mssTemplate(source, scale=1.0, **options):
    """Generates a grain once as a template for packings; see :class:`MssTemplate`.

    :param source: what :func:`generate` takes, or an :class:`MssResult`
    :param float scale: a size factor (the file's units times this)
    :param options: every keyword of :func:`generate` (unknown ones raise TypeError before any work)
    """
    gen, = split('mssTemplate', options, GENERATE_OPTIONS, extra=('source', 'scale'))
    scale = _scale('mssTemplate', scale)
    if isinstance(source, MssResult) and gen:
        raise ValueError('mssTemplate: %s: generation options do nothing for an MssResult' % ', '.join(sorted(gen)))
    if not isinstance(source, MssResult):
        requireVoxelSize('mssTemplate', source, gen)
    return MssTemplate(generate(source, **gen), float(scale))


def _templates(func, templates, gen):
    templates = list(templates) if isinstance(templates, (list, tuple)) else [templates]
    if not templates:
        raise ValueError('%s: give at least one template' % func)
    return [t if isinstance(t, MssTemplate) else mssTemplate(t, **gen) for t in templates]


def _kabsch(Q, P):
    """Rotations R (k, 3, 3) and translations t (k, 3) with P[k] ~ t[k] + R[k] Q, for point sets P (k, n, 3)
    (least squares; Kabsch 1976), all k at once."""
    qc, pc = Q.mean(axis=0), P.mean(axis=1)
    H = np.einsum('ni,knj->kij', Q - qc, P - pc[:, None, :])
    U, _, Vt = np.linalg.svd(H)
    d = np.sign(np.linalg.det(np.einsum('kji,klj->kil', Vt, U)))
    d[d == 0] = 1.0
    D = np.zeros((len(d), 3, 3))
    D[:, 0, 0] = D[:, 1, 1] = 1.0
    D[:, 2, 2] = d
    R = np.einsum('kji,kjl,kml->kim', Vt, D, U)
    return R, pc - np.einsum('kij,j->ki', R, qc)


def _psdSampler(psdSizes, psdCumm, distributeMass):
    """Inverse-CDF sampler of sizes (diameters) from YADE's PSD convention: sieve sizes and cumulative
    fractions (by number, or by mass with *distributeMass*, as in ``SpherePack.makeCloud``)."""
    d = np.asarray(psdSizes, dtype=float)
    F = np.asarray(psdCumm, dtype=float)
    if d.ndim != 1 or len(d) < 2 or len(d) != len(F):
        raise ValueError('mssClumpCloud: psdSizes and psdCumm must be lists of the same length (at least 2)')
    if not (np.all(d > 0) and np.all(np.diff(d) > 0)):
        raise ValueError('mssClumpCloud: psdSizes must be positive and increasing')
    if not (np.all(np.diff(F) >= 0) and F[0] >= 0 and abs(F[-1] - 1) < 1e-9 and F[-1] > F[0]):
        raise ValueError('mssClumpCloud: psdCumm must rise from >= 0 to 1')
    frac = np.diff(F)
    if distributeMass:  # a bin's number share is its mass share over a grain's mass there (~ d^3)
        mid = 0.5 * (d[1:] + d[:-1])
        frac = frac / mid ** 3
    cum = np.concatenate([[0.0], np.cumsum(frac) / frac.sum()])

    def sample(rng, n):
        return np.interp(rng.random(n), cum, d)

    return sample


def _placeByBoundingBalls(rng, lo, hi, radii, periodic, tries=1000):
    """Random sequential placement of balls (largest first) in the box, none overlapping (periodic: minimum
    image). Returns the centres of the ones placed (in the order of *radii*) and their indices."""
    L = hi - lo
    placed, where = [], []
    for i in np.argsort(-radii, kind='stable'):
        r = radii[i]
        if not periodic and np.any(2 * r > L):
            continue
        for _ in range(tries):
            c = lo + (rng.random(3) * L if periodic else r + rng.random(3) * (L - 2 * r))
            if placed:
                P = np.array([p for p, _ in placed])
                d = P - c
                if periodic:
                    d -= L * np.round(d / L)
                if np.any(np.linalg.norm(d, axis=1) < np.array([q for _, q in placed]) + r):
                    continue
            placed.append((c, r))
            where.append(i)
            break
    return [p for p, _ in placed], where


def mssClumpCloud(templates, minCorner, maxCorner, num=-1, periodic=False, seed=-1, psdSizes=None, psdCumm=None,
                  distributeMass=False, mass='target', breakable=False, **options):
    """A random loose packing of clumps, each with its grain's exact mass properties (:func:`mssClump`).

    Without a size distribution, positions and orientations come from ``SpherePack.makeClumpCloud`` (same
    parameters; the templates at their own scale). With ``psdSizes``/``psdCumm`` (YADE's convention: sizes are
    diameters, here of the sphere of the grain's volume; cumulative fractions by number, or by mass with
    ``distributeMass``), each grain gets a size drawn from the distribution, a template at random and a
    uniformly random orientation; grains are placed largest first where their bounding balls overlap no other.

    :param templates: :class:`MssTemplate` objects, or sources to make them from with the generate options
    :param minCorner: the box's lower corner, 3 numbers
    :param maxCorner: the box's upper corner, 3 numbers
    :param int num: number of clumps (-1: as many as fit; required with a size distribution)
    :param bool periodic: place in a periodic cell of the box (minimum image: grains may cross its faces), as
        ``makeClumpCloud(periodic=True)``; set ``O.periodic`` and ``O.cell`` to the box to simulate it
    :param int seed: random seed (-1: random)
    :param psdSizes: a size distribution's sizes (diameters of the sphere of the grain's volume), with psdCumm
    :param psdCumm: its cumulative fractions (by number; by mass with distributeMass), one per size
    :param bool distributeMass: psdCumm are fractions of the mass, not of the number
    :param str mass: 'target' (each grain's exact mass properties) or 'union' (its spheres' union's)
    :param bool breakable: each clump carries its grain's mesh, for :func:`mssSplit` (templates of meshes)
    :param options: :func:`generate` keywords (for sources) and ``utils.sphere`` ones (material, color, ...)
    :return: list of (clumpId, [memberIds])
    """
    func = 'mssClumpCloud'
    gen, body = split(func, options, GENERATE_OPTIONS, bodyOptions(),
                      extra=('templates', 'minCorner', 'maxCorner', 'num', 'periodic', 'seed', 'psdSizes', 'psdCumm',
                             'distributeMass', 'mass', 'breakable'))
    utils, O, me = yadeModules()
    from yade import pack
    mass = _mass(func, mass)
    breakable = _flag(func, 'breakable', breakable)
    if isinstance(num, (bool, np.bool_)) or not isinstance(num, (int, np.integer)) or not (num >= 1 or num == -1):
        raise ValueError('%s: num must be an integer >= 1, or -1 (as many as fit), got %r' % (func, num))
    seed = _seed(func, seed)
    for name, flag in (('periodic', periodic), ('distributeMass', distributeMass)):
        if not isinstance(flag, (bool, np.bool_)):
            raise TypeError('%s: %s must be True or False, got %r' % (func, name, flag))
    lo = vector3(func, 'minCorner', minCorner)
    hi = vector3(func, 'maxCorner', maxCorner)
    if not np.all(hi > lo):
        raise ValueError('%s: maxCorner must exceed minCorner on every axis' % func)
    if (psdSizes is None) != (psdCumm is None):
        raise ValueError('%s: give psdSizes and psdCumm together' % func)
    members = _Members(func, body)
    templates = _templates(func, templates, gen)
    if psdSizes is not None:
        sample = _psdSampler(psdSizes, psdCumm, distributeMass)
        if num < 1:
            raise ValueError('%s: num must be >= 1 with a size distribution, got %r' % (func, num))
        rng = np.random.default_rng(None if seed is None or seed < 0 else seed)
        sizes = sample(rng, int(num))
        which = rng.integers(len(templates), size=int(num))
        scales = np.array([sizes[i] / (2 * templates[w].equivalentRadius) for i, w in enumerate(which)])
        bounding = np.array([scales[i] * templates[w].boundingRadius for i, w in enumerate(which)])
        centres, order = _placeByBoundingBalls(rng, lo, hi, bounding, periodic)
        if len(order) < num:
            warnings.warn('%s: placed %d of %d grains (the box is too full)' % (func, len(order), num))
        plans = [templates[which[i]].plan(c, randomRotation(rng), scales[i], mass) for c, i in zip(centres, order)]
        return _build(func, plans, members, _offsetWarning, _grains(func, templates, [which[i] for i in order],
                                                                    plans, breakable))
    sp = pack.SpherePack()
    sp.makeClumpCloud(me.Vector3(*lo), me.Vector3(*hi), [t.spherePack for t in templates],
                      periodic=bool(periodic), num=int(num), seed=-1 if seed is None else seed)
    rows = np.array([(c[0], c[1], c[2], r, k) for c, r, k in sp.toList()]).reshape(-1, 5)
    rows = rows[np.argsort(rows[:, 4], kind='stable')]
    groups = np.split(rows, np.flatnonzero(np.diff(rows[:, 4])) + 1) if len(rows) else []
    which = []
    for g in groups:
        radii = g[:, 3]
        k = next((i for i, t in enumerate(templates) if len(t.spherePackRadii) == len(radii)
                  and np.allclose(t.spherePackRadii, radii, rtol=1e-12)), None)
        if k is None:
            raise RuntimeError('%s: a clump of the cloud matches no template' % func)
        which.append(k)
    plans = [None] * len(groups)
    for k, t in enumerate(templates):  # every clump of a template at once
        mine = [i for i, w in enumerate(which) if w == k]
        if mine:
            R, tr = _kabsch(t.spherePackCenters, np.array([groups[i][:, :3] for i in mine]))
            for i, p in zip(mine, t.plans(tr, R, mass)):
                plans[i] = p
    return _build(func, plans, members, _offsetWarning, _grains(func, templates, which, plans, breakable))


def _grains(func, templates, which, plans, breakable):
    """Each plan's grain in the world when *breakable* (plan k from template which[k])."""
    return grainsOf(func, [templates[w].result for w in which], plans, breakable)


def mssReplaceByClumps(templates, amounts, fit='inside', seed=None, mass='target', breakable=False, **options):
    """Replaces free spheres of the scene by clumps, as ``O.bodies.replaceByClumps`` does, but with exact mass
    properties and without overlaps: with ``fit='inside'`` each clump's bounding ball is the sphere it replaces
    (YADE's own gives the clump the sphere's volume, so clumps stick out by the ratio of bounding to equivalent
    radius, often 1.3-1.5, and a packing starts overlapping); ``fit='volume'`` is YADE's rule.

    :param templates: :class:`MssTemplate` objects (or sources, with generate options)
    :param amounts: fraction of the free spheres replaced by each template (sum at most 1)
    :param str fit: 'inside' (each clump's bounding ball is the sphere it replaces) or 'volume' (YADE's rule:
        the clump has the sphere's volume)
    :param seed: random seed for which spheres and the orientations (uniform)
    :param str mass: 'target' (each grain's exact mass properties) or 'union' (its spheres' union's)
    :param bool breakable: each clump carries its grain's mesh, for :func:`mssSplit` (templates of meshes)
    :param options: :func:`generate` keywords (for sources) and ``utils.sphere`` ones (material, color, ...)
    :return: list of (clumpId, [memberIds])
    """
    gen, body = split('mssReplaceByClumps', options, GENERATE_OPTIONS, bodyOptions(),
                      extra=('templates', 'amounts', 'fit', 'seed', 'mass', 'breakable'))
    mass = _mass('mssReplaceByClumps', mass)
    breakable = _flag('mssReplaceByClumps', 'breakable', breakable)
    utils, O, me = yadeModules()
    from yade.wrapper import Sphere
    templates = _templates('mssReplaceByClumps', templates, gen)
    amounts = [float(a) for a in (amounts if isinstance(amounts, (list, tuple)) else [amounts])]
    if len(amounts) != len(templates) or min(amounts) < 0 or sum(amounts) > 1 + 1e-12:
        raise ValueError('mssReplaceByClumps: one amount per template, each >= 0, adding up to at most 1')
    if fit not in ('inside', 'volume'):
        raise ValueError("mssReplaceByClumps: fit must be 'inside' or 'volume', got %r" % (fit,))
    free = [b for b in O.bodies if b is not None and isinstance(b.shape, Sphere) and not b.isClumpMember]
    rng = np.random.default_rng(None if seed is None else integer('mssReplaceByClumps', 'seed', seed, 0, INT64_MAX))
    order = rng.permutation(len(free))
    out, k, makers = [], 0, {}
    for t, a in zip(templates, amounts):
        n = int(round(a * len(free)))
        for i in order[k:k + n]:
            b = free[i]
            c = np.array([b.state.pos[0], b.state.pos[1], b.state.pos[2]])
            r = b.shape.radius
            s = r / (t.boundingRadius if fit == 'inside' else t.equivalentRadius)
            mat = body.get('material', b.material)
            key = ('given',) if 'material' in body else (mat.id if mat.id >= 0 else id(mat),)
            if key not in makers:
                makers[key] = _Members('mssReplaceByClumps', dict(body, material=mat))
            plans = [t.plan(c, randomRotation(rng), s, mass)]
            out.append(_build('mssReplaceByClumps', plans, makers[key], _offsetWarning,
                              _grains('mssReplaceByClumps', [t], [0], plans, breakable))[0])
            O.bodies.erase(b.id)
        k += n
    return out
