"""Clump contacts whose stiffness does not depend on the sphere count: ``contactStiffness='grain'``.

Two clumps touch through as many sphere pairs as their sphere counts allow, and YADE's linear law gives each pair
its own stiffness (``Ip2_FrictMat_FrictMat_FrictPhys``: kn = 2 E1 r1 E2 r2 / (E1 r1 + E2 r2)): the stiffness of
a clump pair grows with the sphere count (17x from 10 to 70 spheres, the literature's multi-contact
over-stiffness: Kruggel-Emden et al. 2008, Kodam et al. 2009, Hoehner et al. 2011). With 'grain', a pass over the
interactions every few steps (:func:`contactStiffnessEngine`) gives each pair of bodies one contact's stiffness
of their grains: the same law with each grain's equivalent radius R = (3 M / (4 pi rho))^(1/3) in place of a
sphere's (a wall's or facet's radius infinite, a plain sphere's its own), K = 2 E1 R1 E2 R2 / (E1 R1 + E2 R2),
shared among the pair's member contacts as they come: each takes the lowest rank k free among the pair's contacts
and gets K / k^3 (the first K, the second K / 8, ...), so that a pair is K to 1.2 K stiff whatever the sphere
count, and stays so as contacts break and form. The shear stiffness of each contact scales
with its kn (YADE's ks / kn kept), and the Coulomb limit stays per contact, mu times its normal force, so the pair
slides at mu times its normal force. (Sharing K by each contact's share of the overlap at every step, K d_max /
sum d_j, is exact at each step but not conservative: a contact's stiffness changing under its overlap pumps
energy into the motion, and a compaction never settled.)

What it cannot fix: a concave contact (two lobes of one grain on another) is one pair here, so its second lobe
gets K / 8 or less, not K; the stiffness of a pair does not grow as more of its surfaces engage (a pair is a
linear spring of its first contact's stiffness, near enough); and between passes a new member contact carries
YADE's own stiffness (a new contact starts at zero overlap, so for a few steps it carries little force).

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
    """What the pass knows of its scene: which members belong to clumps asking for it, with each clump's (id, R,
    E), made again when the bodies change; the step of its last look; the contacts it gave a stiffness, by pair
    of bodies. A new or loaded scene starts afresh."""

    REFRESH = 100  # passes between two looks at the bodies, besides a change of their number
    TAG = 'mss.stiffnessPass'  # a scene tag naming the pass that looked at it (a new or loaded scene: none)

    def __init__(self):
        self.key = None
        self.calls = 0
        self.members = {}
        self.last = None
        self.pairs = {}

    def refresh(self, O):
        self.calls += 1
        tag = O.tags[self.TAG] if self.TAG in O.tags.keys() else None
        key = (len(O.bodies), tag)
        if key == self.key and self.calls % self.REFRESH:
            return
        if self.key is None or tag != self.key[1]:  # another scene: nothing of the last one holds
            self.last, self.pairs = None, {}
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


def _pairStiffness(a, b):
    """One contact's stiffness of two sides (group id, radius, young): YADE's law with the grains' radii."""
    (ra, ea), (rb, eb) = a[1:], b[1:]
    if math.isinf(rb):
        return 2.0 * ea * ra
    if math.isinf(ra):
        return 2.0 * eb * rb
    return 2.0 * ea * ra * eb * rb / (ea * ra + eb * rb)


def contactStiffnessStep():
    """The pass (what :func:`contactStiffnessEngine` runs): each new contact of a pair of bodies of which one at
    least is a 'grain' clump gets its share of one contact's stiffness of the pair's grains.

    A contact's stiffness is set once, when it is new: it takes the lowest rank k that none of the pair's
    contacts holds now (the new ones by depth) and gets K / k^3, so the pair's stiffness lies between K and 1.2 K
    however many members touch, and stays there as contacts break and others form (the first contact gone, the
    next new one takes its rank); each contact stays a linear spring (nothing is pumped into the motion). New
    means made real since the last pass (``iterMadeReal``): one look at each real interaction, the rest only for
    the new ones. On its first look at a scene (new, or loaded) the new contacts are those that still have the
    stiffness YADE's Ip2 gave them; the others keep theirs, their rank read back from it."""
    utils, O = _yade()
    p = _PASS
    p.refresh(O)
    if not p.members or p.last == O.iter:
        return
    members = p.members
    its = O.interactions.all(True)
    if p.last is None:
        fresh = [i for i in its if (i.id1 in members or i.id2 in members) and _isFresh(i, O)]
        seen = set((i.id1, i.id2) for i in fresh)
        for i in its:  # what a saved scene's contacts already had: their ranks, from K / k^3
            if (i.id1 in members or i.id2 in members) and (i.id1, i.id2) not in seen:
                a, b = _side(O, p, i.id1), _side(O, p, i.id2)
                k = max(1, int(round((_pairStiffness(a, b) / i.phys.kn) ** (1.0 / 3.0))))
                p.pairs.setdefault((a[0], b[0]), {})[(i.id1, i.id2)] = k
    else:
        last = p.last
        fresh = [i for i in its if i.iterMadeReal > last and (i.id1 in members or i.id2 in members)]
    p.last = O.iter
    if not fresh:
        return
    groups = {}
    for i in fresh:
        a, b = _side(O, p, i.id1), _side(O, p, i.id2)
        groups.setdefault((a, b), []).append(i)
    for (a, b), new in groups.items():
        K = _pairStiffness(a, b)
        held = p.pairs.setdefault((a[0], b[0]), {})
        renewed = set((i.id1, i.id2) for i in new)
        for ids in list(held):  # those that broke, or broke and came back (new again), hold no rank
            if ids in renewed or not _real(O, ids):
                del held[ids]
        taken = set(held.values())
        free = (k for k in range(1, len(held) + len(new) + 1) if k not in taken)
        for i in sorted(new, key=lambda i: -i.geom.penetrationDepth):
            k = next(free)
            ph = i.phys
            kn = K / k ** 3
            ph.ks *= kn / ph.kn
            ph.kn = kn
            held[(i.id1, i.id2)] = k


def _real(O, ids):
    try:
        return O.interactions.has(*ids) and O.interactions[ids].isReal
    except (IndexError, KeyError, RuntimeError):
        return False


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
    if not isinstance(label, str):
        raise TypeError('contactStiffnessEngine: label must be a string, got %r' % (label,))
    return utils.PyRunner(command='import yade_mss.yade as m; m.contactStiffnessStep()', iterPeriod=every,
                          initRun=True, label=label)
