"""yade_mss inside real YADE: run with `yade -n -x tests/yade/test_yade.py` (exit status 0 when all pass)."""
import math
import os
import sys
import unittest

import numpy as np

from yade import utils, pack
from yade.wrapper import *  # noqa: F401,F403 (engines, materials, O)
import yade.minieigenHP as me

from yade_mss import generate, mssClump, mssTemplate, MssResult

sys.path.insert(0, os.path.join(os.environ.get('MSS_TEST_DATA', 'tests/data'), '..', 'yade'))
from clumptools import DATA, ELL, FEMUR, rot, tensor, unionByGrid  # noqa: E402,F401

O = Omega()


class Base(unittest.TestCase):
    def setUp(self):
        O.reset()
        O.materials.append(FrictMat(density=2000, young=1e7, poisson=0.3, frictionAngle=0.5, label='grain'))


class MassAndInertia(Base):
    def test_ellipsoid_target(self):
        cid, ids = mssClump(ELL, nSpheres=10, resolution=103)
        st = O.bodies[cid].state
        V = 4.0 / 3.0 * math.pi * 2.0  # exact ellipsoid, semi-axes 2, 1, 1
        M = 2000 * V
        self.assertLess(abs(st.mass - M) / M, 0.005)
        moments = sorted([st.inertia[0], st.inertia[1], st.inertia[2]])
        exact = sorted(M * np.array([1 + 1, 4 + 1, 4 + 1]) / 5.0)
        for a, b in zip(moments, exact):
            self.assertLess(abs(a - b) / b, 0.005)
        # the axis of the smallest moment is the ellipsoid's long axis (x), within 1 degree
        R = rot(st.ori)
        axis = R[:, int(np.argmin([st.inertia[0], st.inertia[1], st.inertia[2]]))]
        self.assertLess(math.degrees(math.acos(min(1.0, abs(axis[0])))), 1.0)
        np.testing.assert_allclose(np.array(st.pos), 0, atol=1e-9)

    def test_fragment_gets_its_own_mass(self):
        # half the ellipsoid beyond a fragmentation plane x = 0: mass 2000 V / 2, centre of mass at x = 3 a / 8
        cid, ids = mssClump(ELL, nSpheres=8, resolution=60, planes=[((0, 0, 0), (1, 0, 0))])
        st = O.bodies[cid].state
        M = 2000 * 4.0 / 3.0 * math.pi * 2.0 / 2
        # the mesh is cut exactly; 0.5% covers the faceted mesh being inscribed in the ellipsoid (-0.05%)
        self.assertLess(abs(st.mass - M) / M, 0.005)
        self.assertLess(abs(st.pos[0] - 3 * 2.0 / 8) / 0.75, 0.005)
        for i in ids:
            b = O.bodies[i]
            self.assertGreaterEqual(b.state.pos[0] - b.shape.radius, -1e-9)

    def test_union(self):
        r = generate(ELL, nSpheres=10, resolution=60)
        cid, ids = mssClump(r, mass='union')
        st = O.bodies[cid].state
        V, c, I = unionByGrid(r.centers, r.radii, 0.01)
        self.assertLess(abs(st.mass - 2000 * V) / (2000 * V), 0.005)
        np.testing.assert_allclose(np.array(st.pos), c, atol=0.005)
        self.assertLess(np.linalg.norm(tensor(st) - 2000 * I) / np.linalg.norm(2000 * I), 0.005)

    def test_yade_alone_would_double_count_overlaps(self):
        # the motivation: YADE's own sum over two unit spheres one radius apart is 18% heavy
        b = [utils.sphere((0, 0, 0), 1), utils.sphere((1, 0, 0), 1)]
        cid, _ = O.bodies.appendClumped(b)
        exact = 2000 * (8 * math.pi / 3 - 5 * math.pi / 12)
        self.assertGreater(O.bodies[cid].state.mass / exact, 1.17)
        r = MssResult([[0, 0, 0], [1, 0, 0]], [1, 1])
        cid2, _ = mssClump(r, mass='union')
        self.assertLess(abs(O.bodies[cid2].state.mass / exact - 1), 0.005)


class Bodies(Base):
    def test_members_radii_and_positions(self):
        r = generate(FEMUR, nSpheres=20, resolution=40)
        cid, ids = mssClump(r)
        self.assertEqual(len(ids), 20)
        self.assertTrue(O.bodies[cid].isClump)
        for i, c, rad in zip(ids, r.centers, r.radii):
            b = O.bodies[i]
            self.assertEqual(b.clumpId, cid)
            self.assertAlmostEqual(b.shape.radius, rad, places=12)
            np.testing.assert_allclose(np.array(b.state.pos), c, atol=1e-9 * 200)

    def test_material_color_mask(self):
        other = O.materials.append(FrictMat(density=5000, young=1e7, label='heavy'))
        cid, ids = mssClump(ELL, nSpheres=4, resolution=30, material=other, color=(1, 0, 0), mask=6)
        cid2, _ = mssClump(ELL, nSpheres=4, resolution=30, material='grain')
        for i in ids:
            b = O.bodies[i]
            self.assertEqual(b.material.density, 5000)
            self.assertEqual(tuple(b.shape.color), (1, 0, 0))
            self.assertEqual(b.mask, 6)
        self.assertAlmostEqual(O.bodies[cid].state.mass / O.bodies[cid2].state.mass, 2.5, places=9)

    def test_placement(self):
        r = generate(FEMUR, nSpheres=15, resolution=40)
        c0, ids0 = mssClump(r)
        q = me.Quaternion(me.Vector3(0, 0, 1), math.pi / 2)
        c1, ids1 = mssClump(r, center=(10, 20, 30), orientation=q, scale=0.5)
        s0, s1 = O.bodies[c0].state, O.bodies[c1].state
        np.testing.assert_allclose(np.array(s1.pos), [10, 20, 30], atol=1e-9)
        self.assertAlmostEqual(s1.mass / s0.mass, 0.125, places=9)
        R = rot(q)
        expect = 0.5 ** 5 * R.dot(tensor(s0)).dot(R.T)
        self.assertLess(np.linalg.norm(tensor(s1) - expect) / np.linalg.norm(expect), 1e-9)
        # member k: rotated and scaled about the centre of mass
        for a, b in zip(ids0, ids1):
            pa = np.array(O.bodies[a].state.pos) - np.array(s0.pos)
            pb = np.array(O.bodies[b].state.pos) - np.array(s1.pos)
            np.testing.assert_allclose(pb, 0.5 * R.dot(pa), atol=1e-9 * 100)
            self.assertAlmostEqual(O.bodies[b].shape.radius, 0.5 * O.bodies[a].shape.radius, places=12)

    def test_clipped_clump_stays_inside(self):
        cid, ids = mssClump(FEMUR, nSpheres=15, resolution=40, clip=True)
        from yade_mss import _mss, MssResult
        c = np.array([np.array(O.bodies[i].state.pos) for i in ids])
        r = np.array([O.bodies[i].shape.radius for i in ids])
        s = _mss.scoreMesh(*_mss.readMesh(FEMUR), c.ravel().tolist(), r.tolist(), 40, 0.37, 1)
        self.assertEqual(s['outside'], 0.0)
        self.assertEqual(len(ids), 15)

    def test_errors_leave_bodies_unchanged(self):
        mssClump(ELL, nSpheres=3, resolution=20)
        n = len(O.bodies)
        for kw in ({'mass': 'wrong'}, {'scale': -1}, {'center': (0, 0)}, {'nSpheres': 0}):
            with self.assertRaises(ValueError):
                mssClump(ELL, resolution=20, **dict({'nSpheres': 3}, **kw))
            self.assertEqual(len(O.bodies), n)
        with self.assertRaises(ValueError):
            mssClump(MssResult([[0, 0, 0], [1, 0, 0]], [1, 1]))  # no target solid
        self.assertEqual(len(O.bodies), n)


class Dynamics(Base):
    def test_free_rotation_conserves_angular_momentum(self):
        r = generate(FEMUR, nSpheres=30, resolution=50)
        cid, ids = mssClump(r, material='grain')
        O.engines = [ForceResetter(), NewtonIntegrator(damping=0, gravity=(0, 0, 0))]
        st = O.bodies[cid].state
        I = 2000 * r.targetMass.inertia  # the tensor we set, world axes
        w0 = np.array([0.3, -0.2, 0.5])
        L0 = I.dot(w0)
        # YADE integrates an aspherical body's angular momentum (exactAsphericalRot); angVel follows from it
        st.angMom = me.Vector3(*L0)
        O.dt = 1e-4
        O.run(1, True)
        # after one step YADE's angular velocity is that of the tensor we set: L = I omega
        np.testing.assert_allclose(np.array(st.angVel), w0, rtol=1e-3)
        O.run(1000, True)
        # the angular momentum YADE integrates is conserved
        self.assertLess(np.linalg.norm(np.array(st.angMom) - L0) / np.linalg.norm(L0), 1e-6)
        # and it is I omega for our tensor in the current orientation, up to the half step by which YADE's
        # leap-frog angVel lags the orientation (|omega| dt = 6e-5 here)
        L = tensor(st).dot(np.array(st.angVel))
        self.assertLess(np.linalg.norm(L - L0) / np.linalg.norm(L0), 1e-4)
        self.assertGreater(np.linalg.norm(np.array(st.angVel) - w0), 1e-3)  # it does tumble
        # with a hundred times smaller step the lag shrinks a hundredfold: I omega = L0 to 1e-6, so the tensor
        # YADE integrates is the one we set
        st.angMom = me.Vector3(*L0)
        O.dt = 1e-6
        O.run(1000, True)
        L = tensor(st).dot(np.array(st.angVel))
        self.assertLess(np.linalg.norm(L - L0) / np.linalg.norm(L0), 1e-6)
        self.assertLess(np.linalg.norm(np.array(st.angMom) - L0) / np.linalg.norm(L0), 1e-6)

    def test_dropped_clump_comes_to_rest(self):
        O.bodies.append(utils.wall((0, 0, -2), axis=2, sense=1, material='grain'))
        cid, ids = mssClump(ELL, nSpheres=10, resolution=40, material='grain',
                            orientation=(me.Vector3(0, 1, 0), 0.3))
        O.engines = [ForceResetter(),
                     InsertionSortCollider([Bo1_Sphere_Aabb(), Bo1_Wall_Aabb()]),
                     InteractionLoop([Ig2_Sphere_Sphere_ScGeom(), Ig2_Wall_Sphere_ScGeom()],
                                     [Ip2_FrictMat_FrictMat_FrictPhys()], [Law2_ScGeom_FrictPhys_CundallStrack()]),
                     NewtonIntegrator(damping=0.3, gravity=(0, 0, -9.81))]
        O.dt = 0.5 * utils.PWaveTimeStep()
        O.run(20000, True)
        st = O.bodies[cid].state
        self.assertTrue(np.all(np.isfinite(np.array(st.pos))))
        self.assertLess(np.linalg.norm(np.array(st.vel)), 1e-2)
        self.assertGreater(st.pos[2], -2.0)  # on the plane, not through it
        self.assertLess(st.pos[2], -0.5)  # and it did fall


class Converters(Base):
    def test_yade_converters_untouched(self):
        # yade_mss registers no Boost.Python converter: YADE's Eigen types still come back as YADE's types
        f = utils.facet([(0, 0, 0), (1, 0, 0), (0, 1, 0)])
        self.assertIsInstance(f.shape.vertices[0], me.Vector3)


class Settling(Base):
    def test_clumps_settle_in_a_box(self):
        from yade_mss import mssClumpCloud
        t1 = mssTemplate(ELL, nSpheres=6, resolution=30, scale=0.004)
        t2 = mssTemplate(FEMUR, nSpheres=8, resolution=30, scale=0.0001)
        L = 0.06
        clumps = mssClumpCloud([t1, t2], (0, 0, 0), (L, L, 2 * L), num=36, seed=11, material='grain')
        self.assertGreaterEqual(len(clumps), 30)
        walls = [O.bodies.append(utils.wall(x, axis=a, sense=s, material='grain'))
                 for x, a, s in ((0, 0, 1), (L, 0, -1), (0, 1, 1), (L, 1, -1), (0, 2, 1))]
        O.engines = [ForceResetter(),
                     InsertionSortCollider([Bo1_Sphere_Aabb(), Bo1_Wall_Aabb()]),
                     InteractionLoop([Ig2_Sphere_Sphere_ScGeom(), Ig2_Wall_Sphere_ScGeom()],
                                     [Ip2_FrictMat_FrictMat_FrictPhys()], [Law2_ScGeom_FrictPhys_CundallStrack()]),
                     NewtonIntegrator(damping=0.4, gravity=(0, 0, -9.81))]
        O.dt = 0.5 * utils.PWaveTimeStep()

        def kinetic():
            return sum(0.5 * O.bodies[c].state.mass * O.bodies[c].state.vel.squaredNorm() for c, m in clumps)

        history = []
        for _ in range(30):  # 0.4 s of falling and settling
            O.run(2000, True)
            history.append(kinetic())
        peak, late = max(history), history[-1]
        for c, members in clumps:
            p = np.array(O.bodies[c].state.pos)
            self.assertTrue(np.all(np.isfinite(p)))
            self.assertTrue(-0.005 < p[0] < L + 0.005 and -0.005 < p[1] < L + 0.005 and p[2] > -0.005)
        self.assertLess(late, 0.01 * peak)  # the kinetic energy decays: coming to rest
        self.assertTrue(np.all(np.isfinite(history)))


class Templates(Base):
    def test_replace_by_clumps(self):
        t = mssTemplate(ELL, nSpheres=6, resolution=30)
        self.assertEqual(len(t.clumpTemplate.relRadii), 6)
        sp = pack.SpherePack()
        sp.makeCloud((0, 0, 0), (10, 10, 10), rMean=0.8, num=8, seed=1)
        sp.toSimulation(material='grain')
        out = O.bodies.replaceByClumps([t.clumpTemplate], [1.0])
        self.assertEqual(len(out), 8)
        for cid, members in out:
            self.assertEqual(len(members), 6)
            self.assertTrue(O.bodies[cid].isClump)

    def test_make_clump_cloud(self):
        t = mssTemplate(FEMUR, nSpheres=8, resolution=30, scale=0.01)
        # the template is centred at the centre of mass of the union of its spheres
        members = MssResult([tuple(c) for c, r in t.spherePack], [r for c, r in t.spherePack])
        np.testing.assert_allclose(members.unionMass().centroid, 0, atol=1e-3 * t.equivalentRadius)
        sp = pack.SpherePack()
        n = sp.makeClumpCloud((0, 0, 0), (5, 5, 5), [t.spherePack], num=5, seed=3)
        self.assertEqual(n, 5)
        self.assertEqual(len(sp), 5 * 8)


if __name__ == '__main__':
    result = unittest.main(exit=False, verbosity=2).result
    print('%d passed, %d failed' % (result.testsRun - len(result.failures) - len(result.errors),
                                   len(result.failures) + len(result.errors)))
    sys.exit(0 if result.wasSuccessful() else 1)
