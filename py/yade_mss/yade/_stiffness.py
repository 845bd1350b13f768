"""Clump contacts whose stiffness does not depend on the sphere count: ``contactStiffness='grain'``.

Two clumps touch through as many sphere pairs as their sphere counts allow, and YADE's linear law gives each pair
its own stiffness (``Ip2_FrictMat_FrictMat_FrictPhys``: kn = 2 E1 r1 E2 r2 / (E1 r1 + E2 r2)): the stiffness of
a clump pair grows with the sphere count (17x from 10 to 70 spheres, the literature's multi-contact
over-stiffness: Kruggel-Emden et al. 2008, Kodam et al. 2009, Hoehner et al. 2011). With 'grain', a pass over the
interactions every few steps (:func:`contactStiffnessEngine`) gives each pair of bodies one contact's stiffness
of their grains: the same law with each grain's equivalent radius R = (3 M / (4 pi rho))^(1/3) in place of a
sphere's (a wall's or facet's radius infinite, a plain sphere's its own), shared among the pair's member
contacts: each member contact i gets kn_i = K d_max / sum_j d_j, so that the pair's
normal force, sum_i kn_i d_i, is K d_max, d_max the deepest member overlap (the grains' overlap, as more
spheres engage). The shear stiffness of each contact scales with its kn (YADE's ks / kn kept), and the
Coulomb limit stays per contact, mu times its normal force, so the pair slides at mu times its normal force.

What it cannot fix: a concave contact (two lobes of one grain on another) is one pair here, with the deepest
overlap of either lobe; and between passes a new member contact carries YADE's own stiffness.

A clump asks for it through its members' material: a twin of the material whose label ends with MARK (saved
with the scene, taken by the pieces of a clump that breaks; YADE reads nothing else of a label).
"""

import math

MARK = '|mss:grainStiffness'
STIFFNESS = ('spheres', 'grain')


def _yade():
    """YADE's utils and Omega (this module sits under _clumps: it imports nothing of the package)."""
    try:
        from yade import utils
        from yade.wrapper import Omega
    except ImportError:
        raise RuntimeError('this function works in a YADE scene: run the script with yade (yade -n -x script.py)')
    return utils, Omega()


def checkStiffness(func, value):
    if value not in STIFFNESS:
        raise ValueError("%s: contactStiffness must be 'spheres' or 'grain', got %r" % (func, value))
    return value


def grainMaterial(mat):
    """The twin of *mat* that marks 'grain' contact stiffness (made once a material and scene)."""
    utils, O = _yade()
    if (mat.label or '').endswith(MARK):
        return mat
    label = (mat.label or 'material%d' % mat.id) + MARK
    for m in O.materials:
        if m.label == label and type(m) is type(mat):
            return m
    twin = type(mat)()
    for k, v in mat.dict().items():
        if k not in ('id', 'label'):
            setattr(twin, k, v)
    twin.label = label
    O.materials.append(twin)
    return twin


class _Pass(object):
    """Which members belong to clumps asking for it, with each clump's (id, R, E); made again when the bodies
    change."""

    REFRESH = 100  # passes between two looks at the bodies, besides a change of their number

    def __init__(self):
        self.key = None
        self.calls = 0
        self.members = {}

    TAG = 'mss.stiffnessPass'  # a scene tag naming the pass that looked at it (a new or loaded scene: none)

    def refresh(self, O):
        self.calls += 1
        tag = O.tags[self.TAG] if self.TAG in O.tags.keys() else None
        key = (len(O.bodies), tag)
        if key == self.key and self.calls % self.REFRESH:
            return
        token = '%d.%d' % (id(self), self.calls)
        O.tags[self.TAG] = token
        self.key = (len(O.bodies), token)
        self.members = {}
        for b in O.bodies:
            if b is None or not b.isClump:
                continue
            ids = list(b.shape.members.keys())
            if not ids:
                continue
            mat = O.bodies[ids[0]].material
            if not (mat.label or '').endswith(MARK):
                continue
            R = (3.0 * b.state.mass / (4.0 * math.pi * mat.density)) ** (1.0 / 3.0)
            entry = (b.id, R, mat.young)
            for i in ids:
                self.members[i] = entry


_PASS = _Pass()


def _side(O, pass_, i):
    """(group id, radius, young) of interaction body *i*: its clump's grain, or the body itself."""
    e = pass_.members.get(i)
    if e is not None:
        return e
    b = O.bodies[i]
    shape = type(b.shape).__name__
    r = b.shape.radius if shape == 'Sphere' else math.inf
    return (i, r, getattr(b.material, 'young', math.nan))


def contactStiffnessStep():
    """The pass (what :func:`contactStiffnessEngine` runs): every pair of bodies of which one at least is a
    'grain' clump gets one contact's stiffness of its grains, shared among its member contacts."""
    utils, O = _yade()
    p = _PASS
    p.refresh(O)
    if not p.members:
        return
    members = p.members
    groups = {}
    for i in O.interactions:
        if not i.isReal or (i.id1 not in members and i.id2 not in members):
            continue
        a, b = _side(O, p, i.id1), _side(O, p, i.id2)
        groups.setdefault((a, b), []).append(i)
    for (a, b), its in groups.items():
        (ra, ea), (rb, eb) = a[1:], b[1:]
        if math.isinf(rb):
            K = 2.0 * ea * ra
        elif math.isinf(ra):
            K = 2.0 * eb * rb
        else:
            K = 2.0 * ea * ra * eb * rb / (ea * ra + eb * rb)
        # a contact's stiffness is set once, when it is new (still YADE's own, from its spheres' radii): the
        # k-th contact of the pair gets K / k^3, so the pair's stiffness lies between K and 1.2 K however many
        # members touch, and each contact stays a linear spring (nothing is pumped into the motion)
        fresh = [i for i in its if _isFresh(i, O)]
        if not fresh:
            continue
        k = len(its) - len(fresh)
        for i in sorted(fresh, key=lambda i: -i.geom.penetrationDepth):
            k += 1
            ph = i.phys
            kn = K / k ** 3
            ph.ks *= kn / ph.kn
            ph.kn = kn


def _isFresh(i, O):
    """Whether interaction *i* still has the stiffness YADE's Ip2 gave it (2 E1 r1 E2 r2 / (E1 r1 + E2 r2))."""
    g = i.geom
    e1, e2 = O.bodies[i.id1].material.young, O.bodies[i.id2].material.young
    r1, r2 = g.refR1, g.refR2
    if r1 <= 0:
        r1 = r2
    if r2 <= 0:
        r2 = r1
    own = 2.0 * e1 * r1 * e2 * r2 / (e1 * r1 + e2 * r2)
    return abs(i.phys.kn - own) <= 1e-9 * own


def contactStiffnessEngine(every=10, label='mssContactStiffness'):
    """A ``PyRunner`` running :func:`contactStiffnessStep` every *every* steps, for clumps made with
    ``contactStiffness='grain'``: put it in ``O.engines`` after the ``InteractionLoop``. It is saved with the
    scene (``O.save``).

    :param int every: steps between passes (1: exact at every step; the pass costs about 7 us an interaction in
        Python, a step of YADE about 4 us a sphere)
    :param str label: the engine's label
    """
    utils, O = _yade()
    if isinstance(every, bool) or not isinstance(every, int) or every < 1:
        raise ValueError('contactStiffnessEngine: every must be an integer >= 1, got %r' % (every,))
    return utils.PyRunner(command='import yade_mss.yade as m; m.contactStiffnessStep()', iterPeriod=every,
                          initRun=True, label=label)
