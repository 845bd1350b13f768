"""Inside YADE an mssClump clump behaves as YADE's own clump of the same spheres (``appendClumped``) in everything
but the clump body's exact mass properties: members, contact physics of every law that reads masses, time steps,
VTK fields; records that never apply to another clump; fixed clumps. Side by side, in real YADE.
Run: yade -n -x tests/yade/test_clump_parity.py"""
import math
import os
import sys
import tempfile
import unittest
import warnings

import numpy as np

sys.path.insert(0, os.path.join(os.environ.get('MSS_TEST_DATA', 'tests/data'), '..', 'yade'))
from clumptools import ELL, FEMUR, ballSums, meshMass, readStlTriangles, vec  # noqa: E402

from yade import utils  # noqa: E402
from yade.wrapper import *  # noqa: F401,F403,E402
import yade.minieigenHP as me  # noqa: E402

from yade_mss import generate, mssClump, mssClumpCloud, mssTemplate, restoreClumpProperties, totalMass  # noqa: E402

O = Omega()
RHO = 2000.0
SHIFT = np.array([10.0, 0, 0])
_cache = {}


def ellipsoid10():
    if 'e' not in _cache:
        _cache['e'] = generate(ELL, nSpheres=10, resolution=30)
    return _cache['e']


def femur20():
    if 'f' not in _cache:
        _cache['f'] = generate(FEMUR, nSpheres=20, resolution=50)
    return _cache['f']


def plainClump(r, shift, **body):
    return O.bodies.appendClumped([utils.sphere(tuple(c + shift), float(rad), **body) for c, rad in zip(r.centers, r.radii)])


def values(obj):
    """Every numeric attribute of a YADE object (its dict(), attribute by attribute where dict() cannot convert
    one, as ViscElCapPhys's CapillarType), as float arrays."""
    out = {}
    names = [n for n in dir(obj) if not n.startswith('_')]
    for n in names:
        try:
            v = getattr(obj, n)
        except TypeError:
            continue
        if callable(v) or isinstance(v, (str, bytes)):
            continue
        try:
            a = np.array([v[i] for i in range(len(v))] if hasattr(v, '__len__') else [v], dtype=float)
        except (TypeError, ValueError):
            continue
        out[n] = a.ravel()
    return out


# (name, the clump's material, the free sphere's (None: the same), Ip2, Law2, 6-D geometry): every Ip2 functor of
# YADE 2023.02a for sphere-sphere contacts with a Law2 to run it (KnKsPhys's law takes another geometry; the
# Delaunay capillary and partial-saturation ones need a flow engine; LubricationPhys's implicit law does not
# return from a contact set up so)
LAWS = [
    ('FrictPhys', lambda: FrictMat(density=RHO, young=1e7), None, Ip2_FrictMat_FrictMat_FrictPhys,
     Law2_ScGeom_FrictPhys_CundallStrack, False),
    ('ViscElPhys', lambda: ViscElMat(density=RHO, tc=1e-3, en=0.5, et=0.5, frictionAngle=0.5), None,
     Ip2_ViscElMat_ViscElMat_ViscElPhys, Law2_ScGeom_ViscElPhys_Basic, False),
    ('ViscElCapPhys', lambda: ViscElCapMat(density=RHO, tc=1e-3, en=0.5, et=0.5, frictionAngle=0.5, Capillar=True,
                                           Vb=1e-4, gamma=0.07, CapillarType='Willett_numeric'), None,
     Ip2_ViscElCapMat_ViscElCapMat_ViscElCapPhys, Law2_ScGeom_ViscElCapPhys_Basic, False),
    ('MindlinPhys', lambda: FrictMat(density=RHO, young=1e7, poisson=0.3), None,
     lambda: Ip2_FrictMat_FrictMat_MindlinPhys(en=0.5, es=0.5), Law2_ScGeom_MindlinPhys_Mindlin, False),
    ('MindlinCapillaryPhys', lambda: FrictMat(density=RHO, young=1e7, poisson=0.3), None,
     lambda: Ip2_FrictMat_FrictMat_MindlinCapillaryPhys(en=0.5, es=0.5), Law2_ScGeom_MindlinPhys_Mindlin, False),
    ('LudingPhys', lambda: LudingMat(density=RHO, k1=1e5, kp=5e5, kc=1e4, ks=5e4, PhiF=0.5, G0=0.1,
                                         frictionAngle=0.5),
     None, Ip2_LudingMat_LudingMat_LudingPhys, Law2_ScGeom_LudingPhys_Basic, False),
    ('FrictViscoPhys', lambda: FrictViscoMat(density=RHO, young=1e7, poisson=0.3, betan=0.5), None,
     Ip2_FrictViscoMat_FrictViscoMat_FrictViscoPhys, Law2_ScGeom_FrictViscoPhys_CundallStrackVisco, False),
    ('FrictMat-FrictViscoPhys', lambda: FrictMat(density=RHO, young=1e7, poisson=0.3),
     lambda: FrictViscoMat(density=RHO, young=1e7, poisson=0.3, betan=0.5),
     Ip2_FrictMat_FrictViscoMat_FrictViscoPhys, Law2_ScGeom_FrictViscoPhys_CundallStrackVisco, False),
    ('ViscoFrictPhys', lambda: FrictMat(density=RHO, young=1e7, poisson=0.3), None,
     Ip2_FrictMat_FrictMat_ViscoFrictPhys, Law2_ScGeom_ViscoFrictPhys_CundallStrack, False),
    ('CohFrictPhys', lambda: CohFrictMat(density=RHO, young=1e7, poisson=0.3, normalCohesion=1e3,
                                         shearCohesion=1e3), None,
     Ip2_CohFrictMat_CohFrictMat_CohFrictPhys, Law2_ScGeom6D_CohFrictPhys_CohesionMoment, True),
    ('CpmPhys', lambda: CpmMat(density=RHO, young=1e7, poisson=0.2, epsCrackOnset=1e-4, relDuctility=30,
                               sigmaT=3e6), None, Ip2_CpmMat_CpmMat_CpmPhys, Law2_ScGeom_CpmPhys_Cpm, False),
    ('JCFpmPhys', lambda: JCFpmMat(density=RHO, young=1e7, poisson=0.3, cohesion=1e3, tensileStrength=1e3), None,
     Ip2_JCFpmMat_JCFpmMat_JCFpmPhys, Law2_ScGeom_JCFpmPhys_JointedCohesiveFrictionalPM, False),
    ('MortarPhys', lambda: MortarMat(density=RHO, young=1e7, poisson=0.3), None, Ip2_MortarMat_MortarMat_MortarPhys,
     Law2_ScGeom_MortarPhys_Lourenco, False),
    ('CapillaryPhys', lambda: FrictMat(density=RHO, young=1e7, poisson=0.3), None, Ip2_FrictMat_FrictMat_CapillaryPhys,
     Law2_ScGeom_FrictPhys_CundallStrack, False),
]


def contactScene(law, r, spoil=None):
    """Our clump, then (a scene of its own) a plain one of exactly the same spheres (our members' coordinates),
    each hit by a free sphere moving onto its top member: the same geometry and velocity, one step.
    :return: [({member index: phys values}, force, torque on the free sphere)] x 2"""
    name, mat, mat2, ip2, law2, six = law
    out, where = [], None
    for ours in (True, False):
        O.reset()
        m = O.materials.append(mat())
        m2 = O.materials.append(mat2()) if mat2 else m
        if ours:
            cid, ids = mssClump(r, material=m)
            where = [(vec(O.bodies[i].state.pos), O.bodies[i].shape.radius) for i in ids]
            if spoil:
                spoil((cid, ids))
        else:
            cid, ids = O.bodies.appendClumped([utils.sphere(tuple(p), rad, material=m) for p, rad in where])
        k = int(np.argmax([p[2] + rad for p, rad in where]))
        top = max(p[2] + rad for p, rad in where)
        b = utils.sphere((where[k][0][0], where[k][0][1], top + 0.3 - 0.01), 0.3, material=m2)
        b.state.vel = me.Vector3(0.01, 0.02, -0.5)
        fid = O.bodies.append(b)
        O.engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb()]),
                     InteractionLoop([Ig2_Sphere_Sphere_ScGeom6D() if six else Ig2_Sphere_Sphere_ScGeom()], [ip2()],
                                     [law2()]),
                     NewtonIntegrator(gravity=(0, 0, 0))]
        O.dt = 1e-7
        O.run(1, True)
        d = {}
        for i in O.bodies[fid].intrs():
            other = i.id1 if i.id2 == fid else i.id2
            if other in ids:
                d[ids.index(other)] = values(i.phys)
        out.append((d, vec(O.forces.f(fid)), vec(O.forces.t(fid))))
    return out


class Members(unittest.TestCase):
    def setUp(self):
        O.reset()
        self.mat = O.materials.append(FrictMat(density=RHO, young=1e7, poisson=0.3, frictionAngle=0.5))

    def test_members_are_utils_sphere_bodies(self):
        r = femur20()
        for body in ({}, dict(mask=5, wire=True, highlight=True, color=(0.1, 0.2, 0.3)), dict(fixed=True)):
            O.reset()
            self.mat = O.materials.append(FrictMat(density=RHO, young=1e7))
            cid, ids = mssClump(r, **body)
            pc, pids = plainClump(r, np.zeros(3), **body)
            for i, j in zip(ids, pids):
                a, b = O.bodies[i], O.bodies[j]
                for attr in ('mask', 'bounded', 'aspherical', 'dynamic', 'isClumpMember', 'groupMask'):
                    self.assertEqual(getattr(a, attr), getattr(b, attr), attr)
                self.assertIs(type(a.state), type(b.state))
                self.assertEqual(a.material.id, b.material.id)
                self.assertEqual(a.state.mass, b.state.mass)  # bit for bit: rho V
                self.assertEqual(vec(a.state.inertia).tolist(), vec(b.state.inertia).tolist())  # 2/5 m r^2
                self.assertEqual(a.state.blockedDOFs, b.state.blockedDOFs)
                self.assertEqual((a.shape.radius, a.shape.wire, a.shape.highlight),
                                 (b.shape.radius, b.shape.wire, b.shape.highlight))
                if 'color' in body:
                    self.assertEqual(vec(a.shape.color).tolist(), vec(b.shape.color).tolist())
                self.assertLess(np.abs(vec(a.state.pos) - vec(b.state.pos)).max(), 1e-9)
            # only the clump bodies differ: ours has the grain's mass, YADE's the balls' sum (overlaps twice)
            V, c, I = meshMass(readStlTriangles(FEMUR))
            self.assertLess(abs(O.bodies[cid].state.mass / (RHO * V) - 1), 1e-9)
            Mb = ballSums(r.centers, r.radii, RHO)[0]
            self.assertLess(abs(O.bodies[pc].state.mass / Mb - 1), 1e-12)

    def test_random_colours_vary_and_the_users_random_is_kept(self):
        import random
        random.seed(5)
        expected = random.random()
        random.seed(5)
        cid, ids = mssClump(ellipsoid10())
        self.assertEqual(random.random(), expected)  # utils.sphere reseeds it for every sphere; we do not
        colours = {tuple(vec(O.bodies[i].shape.color)) for i in ids}
        self.assertEqual(len(colours), len(ids))
        self.assertTrue(all(0 <= c <= 1 for col in colours for c in col))


class Physics(unittest.TestCase):
    def test_contact_physics_of_every_law(self):
        r = ellipsoid10()
        table = []
        for law in LAWS:
            (ours, fo, to), (plain, fp, tp) = contactScene(law, r)
            self.assertEqual(sorted(ours), sorted(plain), law[0])
            self.assertGreater(len(ours), 0, law[0])
            for k in ours:
                for attr, a in ours[k].items():
                    b = plain[k][attr]
                    scale = max(np.abs(a[np.isfinite(a)]).max(initial=0), np.abs(b[np.isfinite(b)]).max(initial=0))
                    ok = np.array_equal(np.isnan(a), np.isnan(b)) and np.all(
                        np.abs(np.nan_to_num(a - b, nan=0.0)) <= 1e-12 * scale)
                    self.assertTrue(ok, '%s.%s: ours %s, plain %s' % (law[0], attr, a, b))
            scale = max(np.abs(fp).max(), 1e-300)
            self.assertLess(np.abs(fo - fp).max() / scale, 1e-12, law[0])
            kn = ours[min(ours)].get('kn', [float('nan')])[0]
            table.append((law[0], kn, plain[min(plain)].get('kn', [float('nan')])[0], np.linalg.norm(fp),
                          np.linalg.norm(fo)))
        print('\nparity (first contact): law, kn plain, kn ours, |F| plain, |F| ours')
        for name, kn, knp, f1, f2 in table:
            print('  %-24s %-12.6g %-12.6g %-12.6g %-12.6g' % (name, knp, kn, f1, f2))

    def test_the_comparison_sees_member_masses(self):
        # members carrying 0.3 of their mass (the old shares) change ViscElPhys's kn and FrictViscoPhys's cn
        def spoil(clump):
            for i in clump[1]:
                O.bodies[i].state.mass *= 0.3
        r = ellipsoid10()
        for name, attr in (('ViscElPhys', 'kn'), ('FrictViscoPhys', 'cn'), ('MindlinPhys', None)):
            law = next(l for l in LAWS if l[0] == name)
            (ours, fo, to), (plain, fp, tp) = contactScene(law, r, spoil)
            k = min(ours)
            if attr:
                self.assertGreater(abs(ours[k][attr][0] / plain[k][attr][0] - 1), 0.01)
            else:  # Mindlin's damping reads the masses in the law: the force
                self.assertGreater(np.abs(fo - fp).max() / np.abs(fp).max(), 1e-6)

    def test_time_steps(self):
        r = femur20()
        steps = []
        for ours in (True, False):
            O.reset()
            m = O.materials.append(FrictMat(density=RHO, young=1e7, poisson=0.3, frictionAngle=0.5))
            for k in range(3):
                if ours:
                    mssClump(r, center=tuple(np.array([0, 0, 1.0]) * k * 300), material=m)
                else:
                    plainClump(r, np.array([0, 0, 1.0]) * k * 300 - np.array(r.targetMass.centroid), material=m)
            pw = utils.PWaveTimeStep()
            steps.append((pw, sum(1 for b in O.bodies if b.isClumpMember)))
        self.assertEqual(steps[0][1], steps[1][1])
        self.assertLess(abs(steps[0][0] / steps[1][0] - 1), 1e-12)  # it was 1.85x smaller on the femur

    def test_global_stiffness_time_stepper_on_touching_members(self):
        # two clumps pressed together: GSTS reads the clumps' own masses and inertias (which differ, by design)
        # and the members' contacts (which must not)
        r = ellipsoid10()
        found = []
        for ours in (True, False):
            O.reset()
            m = O.materials.append(FrictMat(density=RHO, young=1e7, poisson=0.3, frictionAngle=0.5))
            k = int(np.argmax(r.centers[:, 2] + r.radii))
            if ours:
                mssClump(r, material=m)
            else:
                plainClump(r, np.zeros(3), material=m)
            top = float((r.centers[:, 2] + r.radii).max())
            O.bodies.append(utils.sphere((r.centers[k, 0], r.centers[k, 1], top + 0.29), 0.3, material=m))
            O.engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb()]),
                         InteractionLoop([Ig2_Sphere_Sphere_ScGeom()], [Ip2_FrictMat_FrictMat_FrictPhys()],
                                         [Law2_ScGeom_FrictPhys_CundallStrack()]),
                         GlobalStiffnessTimeStepper(timestepSafetyCoefficient=0.8, timeStepUpdateInterval=1,
                                                    defaultDt=1e-3, label='gsts'),
                         NewtonIntegrator(gravity=(0, 0, 0))]
            O.dt = 1e-6
            O.run(3, True)
            found.append(O.dt)
        # the free sphere is the stiffest body, so both steps are its: equal
        self.assertLess(abs(found[0] / found[1] - 1), 1e-12)

    def test_vtk_mass_fields(self):
        r = femur20()
        O.reset()
        m = O.materials.append(FrictMat(density=RHO, young=1e7))
        cid, ids = mssClump(r, material=m)
        pc, pids = plainClump(r, np.array([300.0, 0, 0]), material=m)
        with tempfile.TemporaryDirectory() as d:
            O.engines = [ForceResetter(), VTKRecorder(fileName=os.path.join(d, 'rec-'), recorders=['spheres', 'mass'],
                                                      iterPeriod=1, ascii=True), NewtonIntegrator(gravity=(0, 0, 0))]
            O.dt = 1e-4
            O.run(1, True)
            with open(os.path.join(d, [f for f in os.listdir(d) if 'spheres' in f][0])) as f:
                text = f.read()
            block = text.split('Name="mass"')[1].split('>', 1)[1].split('<')[0]
            masses = np.array(block.split(), dtype=float)
        n = len(ids)
        self.assertEqual(len(masses), 2 * n)
        np.testing.assert_allclose(masses[:n], masses[n:], rtol=1e-12)
        np.testing.assert_allclose(masses[:n], RHO * 4 / 3 * math.pi * r.radii ** 3, rtol=1e-12)


class Fixed(unittest.TestCase):
    def setUp(self):
        O.reset()
        O.materials.append(FrictMat(density=RHO, young=1e7, poisson=0.3, frictionAngle=0.5))

    def test_fixed_means_the_clump(self):
        # the bug: fixed=True made only the members non-dynamic and the clump fell 4.0 m in 1 s
        r = ellipsoid10()
        for body in (dict(fixed=True), dict(dynamic=False)):
            O.reset()
            O.materials.append(FrictMat(density=RHO, young=1e7, poisson=0.3, frictionAngle=0.5))
            with warnings.catch_warnings():
                warnings.simplefilter('ignore', DeprecationWarning)  # YADE's word on dynamic=
                cid, ids = mssClump(r, **body)
            pc, pids = plainClump(r, SHIFT)  # a free clump beside it, for contrast
            p0 = vec(O.bodies[cid].state.pos)
            top = float((r.centers[:, 2] + r.radii).max())
            k = int(np.argmax(r.centers[:, 2] + r.radii))
            ball = O.bodies.append(utils.sphere((r.centers[k, 0], r.centers[k, 1], top + 0.5), 0.3))
            self.assertFalse(O.bodies[cid].dynamic)
            O.engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb()]),
                         InteractionLoop([Ig2_Sphere_Sphere_ScGeom()], [Ip2_FrictMat_FrictMat_FrictPhys()],
                                         [Law2_ScGeom_FrictPhys_CundallStrack()]),
                         NewtonIntegrator(gravity=(0, 0, -9.81), damping=0.2)]
            O.dt = 0.5 * utils.PWaveTimeStep()
            touched = 0
            for chunk in range(50):
                O.run(int(0.01 / O.dt), True)
                touched += len(O.bodies[ball].intrs())
            self.assertLess(np.abs(vec(O.bodies[cid].state.pos) - p0).max(), 1e-12)  # put, under gravity and the ball
            self.assertGreater(touched, 0)  # the ball hit it
            self.assertGreater(O.bodies[ball].state.pos[2], top)  # and did not go through
            self.assertLess(vec(O.bodies[pc].state.pos)[2], p0[2] - 0.5)  # the free one fell


class Records(unittest.TestCase):
    """A record applies only to the clump it was made for."""

    def setUp(self):
        O.reset()
        O.materials.append(FrictMat(density=RHO, young=1e7))

    def assertUntouched(self, cid, before):
        st = O.bodies[cid].state
        self.assertEqual((st.mass, vec(st.pos).tolist()), before)

    def state(self, cid):
        st = O.bodies[cid].state
        return (st.mass, vec(st.pos).tolist())

    def test_clear_then_a_plain_clump_with_the_same_ids(self):
        # the bug: restoreClumpProperties() rewrote a plain clump's mass from 57192 to 16746
        r = ellipsoid10()
        cid, ids = mssClump(r)
        O.bodies.clear()
        pc, pids = plainClump(r, np.zeros(3))  # the same spheres at the same places, the same ids
        self.assertEqual(pc, cid)
        before = self.state(pc)
        with warnings.catch_warnings(record=True) as w:
            warnings.simplefilter('always')
            self.assertEqual(restoreClumpProperties(), [])  # the record went with its clump
        self.assertEqual(w, [])
        self.assertUntouched(pc, before)
        self.assertIsNone(O.bodies[pc].material)  # as YADE's clumps

    def test_a_record_moved_to_another_clump_is_dropped(self):
        # the fingerprint: even the same spheres at the same places, clumped by YADE, do not match
        r = ellipsoid10()
        cid, ids = mssClump(r)
        pc, pids = plainClump(r, np.zeros(3))
        O.bodies[pc].material = O.bodies[cid].material
        before = self.state(pc)
        with warnings.catch_warnings(record=True) as w:
            warnings.simplefilter('always')
            O.bodies.updateClumpProperties(discretization=0)
            done = restoreClumpProperties()
        self.assertEqual(done, [(cid, 'grain')])
        self.assertTrue(any('another clump' in str(x.message) for x in w), [str(x.message) for x in w])
        self.assertUntouched(pc, before)
        self.assertIsNone(O.bodies[pc].material)  # dropped
        self.assertEqual(restoreClumpProperties(), [(cid, 'grain')])  # no second warning for it

    def test_a_damaged_record_is_dropped(self):
        cid, ids = mssClump(ellipsoid10())
        # damaged, and of the older format (frame of member 0): neither is applied
        good = O.bodies[cid].material.label
        for label in ('mss3:not base64!', 'mss2:' + good[5:]):
            O.bodies[cid].material = Material(label=label, density=0)
            with warnings.catch_warnings(record=True) as w:
                warnings.simplefilter('always')
                self.assertEqual(restoreClumpProperties(), [])
            self.assertTrue(any('not readable' in str(x.message) for x in w))

    def test_clear_then_other_spheres(self):
        cid, ids = mssClump(ellipsoid10())
        O.bodies.clear()
        pc, pids = plainClump(femur20(), np.zeros(3))
        before = self.state(pc)
        with warnings.catch_warnings(record=True):
            warnings.simplefilter('always')
            self.assertEqual(restoreClumpProperties(), [])
        self.assertUntouched(pc, before)

    def test_erase_then_a_new_clump(self):
        r = ellipsoid10()
        cid, ids = mssClump(r)
        O.bodies.erase(cid, True)
        pc, pids = plainClump(r, np.zeros(3))
        before = self.state(pc)
        with warnings.catch_warnings(record=True):
            warnings.simplefilter('always')
            restoreClumpProperties()
        self.assertUntouched(pc, before)

    def test_clear_then_ours_again(self):
        r = ellipsoid10()
        mssClump(r)
        O.bodies.clear()
        cid, ids = mssClump(r, center=(1, 2, 3))
        O.bodies.updateClumpProperties(discretization=0)
        self.assertEqual(restoreClumpProperties(), [(cid, 'grain')])
        self.assertLess(np.abs(vec(O.bodies[cid].state.pos) - [1, 2, 3]).max(), 1e-9)

    def test_reset_drops_every_record(self):
        r = ellipsoid10()
        mssClump(r)
        O.reset()
        O.materials.append(FrictMat(density=RHO))
        pc, pids = plainClump(r, np.zeros(3))
        before = self.state(pc)
        self.assertEqual(restoreClumpProperties(), [])
        self.assertUntouched(pc, before)

    def test_save_load_and_tmp_keep_the_fingerprint(self):
        r = ellipsoid10()
        cid, ids = mssClump(r)
        exact = self.state(cid)
        with tempfile.TemporaryDirectory() as d:
            f = os.path.join(d, 's.yade.gz')
            O.save(f)
            O.reset()
            O.load(f)
            O.bodies.updateClumpProperties(discretization=0)
            self.assertEqual(restoreClumpProperties(), [(cid, 'grain')])
            self.assertLess(abs(O.bodies[cid].state.mass / exact[0] - 1), 1e-12)
            O.saveTmp('a')
            O.bodies.clear()
            pc, pids = plainClump(r, np.zeros(3))
            with warnings.catch_warnings(record=True):
                warnings.simplefilter('always')
                self.assertEqual(restoreClumpProperties(), [])
            O.loadTmp('a')  # the saved scene holds its clump and the record again
            O.bodies.updateClumpProperties(discretization=0)
            self.assertEqual(restoreClumpProperties(), [(cid, 'grain')])
            self.assertLess(abs(O.bodies[cid].state.mass / exact[0] - 1), 1e-12)

    def test_random_api_sequences(self):
        # 100 random sequences of the clump API; after each, every plain clump keeps the sums of YADE's spheres
        # and every clump of ours its exact mass (the bug: 6 of 100 rewrote a plain clump)
        rs = [ellipsoid10(), femur20()]
        exact = [RHO * r.targetMass.volume for r in rs]
        rng = np.random.default_rng(29)
        for seq in range(100):
            O.reset()
            O.materials.append(FrictMat(density=RHO, young=1e7))
            kinds = {}  # clump id: ('ours', which) or ('plain', which)
            with warnings.catch_warnings():
                warnings.simplefilter('ignore')
                for step in range(8):
                    op = rng.integers(6)
                    live = [c for c in kinds if O.bodies[c] is not None]
                    if op == 0:
                        w = int(rng.integers(2))
                        kinds[mssClump(rs[w], center=tuple(rng.random(3) * 100))[0]] = ('ours', w)
                    elif op == 1:
                        w = int(rng.integers(2))
                        kinds[plainClump(rs[w], rng.random(3) * 100)[0]] = ('plain', w)
                    elif op == 2:
                        O.bodies.clear()
                        kinds = {}
                    elif op == 3 and live:
                        c = live[int(rng.integers(len(live)))]
                        O.bodies.erase(c, True)
                        del kinds[c]
                    elif op == 4:
                        O.bodies.updateClumpProperties(discretization=0)
                    else:
                        restoreClumpProperties()
                restoreClumpProperties()
            for c, (kind, w) in kinds.items():
                M = O.bodies[c].state.mass
                if kind == 'plain':
                    self.assertLess(abs(M / ballSums(rs[w].centers, rs[w].radii, RHO)[0] - 1), 1e-12, (seq, c))
                else:
                    self.assertLess(abs(M / exact[w] - 1), 1e-9, (seq, c))


class Speed(unittest.TestCase):
    def test_a_cloud_of_templates_gets_exact_clumps(self):
        O.reset()
        O.materials.append(FrictMat(density=RHO, young=1e7))
        t = mssTemplate(ELL, nSpheres=10, resolution=30)
        clumps = mssClumpCloud([t], (0, 0, 0), (40, 40, 40), num=50, seed=3)
        self.assertEqual(len(clumps), 50)
        M = RHO * t.result.targetMass.volume
        for cid, ids in clumps:
            self.assertLess(abs(O.bodies[cid].state.mass / M - 1), 1e-9)
            for i in ids:
                b = O.bodies[i]
                self.assertLess(abs(b.state.mass / (RHO * 4 / 3 * math.pi * b.shape.radius ** 3) - 1), 1e-14)
        O.bodies.updateClumpProperties(discretization=0)
        self.assertEqual(len(restoreClumpProperties()), 50)
        for cid, ids in clumps:
            self.assertLess(abs(O.bodies[cid].state.mass / M - 1), 1e-9)
        self.assertLess(abs(totalMass() / (50 * M) - 1), 1e-9)


if __name__ == '__main__':
    result = unittest.main(exit=False, verbosity=2).result
    print('%d passed, %d failed' % (result.testsRun - len(result.failures) - len(result.errors),
                                   len(result.failures) + len(result.errors)))
    sys.exit(0 if result.wasSuccessful() else 1)
