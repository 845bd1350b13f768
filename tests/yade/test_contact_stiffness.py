"""contactStiffness='grain': a clump pair's stiffness that does not depend on the sphere count, in real YADE; the
default ('spheres') is YADE's own. Run: yade -n -x tests/yade/test_contact_stiffness.py"""
import os
import shutil
import sys
import tempfile
import unittest

import numpy as np

from yade import utils
from yade.wrapper import *  # noqa: F401,F403

from yade_mss import (contactStiffnessEngine, generate, mssAssembly, mssClump, mssClumpCloud, mssReplaceByClumps,
                      mssSplit, mssTemplate, restoreClumpProperties)
from yade_mss.yade import GRAIN_STIFFNESS_MARK

O = Omega()  # noqa: F405
DATA = os.environ.get('MSS_TEST_DATA', os.path.join('tests', 'data'))
ELL = os.path.join(DATA, 'ellipsoid_2_1_1.stl')
RESULTS = {}


def result(n):
    if n not in RESULTS:
        RESULTS[n] = generate(ELL, nSpheres=n)
    return RESULTS[n]


def engines(stiffness):
    loop = InteractionLoop([Ig2_Sphere_Sphere_ScGeom(), Ig2_Wall_Sphere_ScGeom()],  # noqa: F405
                           [Ip2_FrictMat_FrictMat_FrictPhys()], [Law2_ScGeom_FrictPhys_CundallStrack()])  # noqa
    extra = [contactStiffnessEngine(every=1)] if stiffness == 'grain' else []
    return ([ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb(), Bo1_Wall_Aabb()]), loop]  # noqa: F405
            + extra + [NewtonIntegrator(damping=0)])  # noqa: F405


def pairStiffness(n, direction, overlap, stiffness):
    """Two fixed clumps of the ellipsoid, the second moved along *direction* to *overlap* (a fraction of the
    equivalent diameter) past the first touch of their spheres: the secant stiffness F / overlap and the member
    pairs in contact."""
    O.reset()
    mat = O.materials.append(FrictMat(young=1e8, poisson=0.3, frictionAngle=0.5, density=2000))  # noqa: F405
    r = result(n)
    u = np.asarray(direction, float) / np.linalg.norm(direction)
    c, rad = r.centers, r.radii

    def gap(d):
        return (np.linalg.norm(c[:, None] - (c[None] + d * u), axis=2) - rad[:, None] - rad[None]).min()
    lo, hi = 0.0, 10.0
    for _ in range(100):  # the first touch, by bisection on the gap
        m = 0.5 * (lo + hi)
        lo, hi = (m, hi) if gap(m) < 0 else (lo, m)
    dv = 2 * (3 * r.targetMass.volume / (4 * np.pi)) ** (1 / 3)
    C = r.targetMass.centroid
    mssClump(r, center=tuple(C), material=mat, fixed=True, contactStiffness=stiffness)
    b, bm = mssClump(r, center=tuple(C + (hi - overlap * dv) * u), material=mat, fixed=True,
                     contactStiffness=stiffness)
    O.engines = engines(stiffness)
    O.dt = 1e-6
    for _ in range(3):
        O.step()
    F = sum(np.array(O.forces.f(i)) for i in bm)
    return abs(F.dot(u)) / (overlap * dv), sum(1 for i in O.interactions if i.isReal)


class PairStiffness(unittest.TestCase):
    def test_the_count_does_not_stiffen_a_pair(self):
        # the measure: max / min over n = 10, 30, 70 of the secant stiffness, at 0.5 % and 2 % overlap
        for name, u in (('tip', (1, 0, 0)), ('side', (0, 1, 0)), ('45 degrees', (1, 1, 0))):
            for overlap in (0.005, 0.02):
                with self.subTest(direction=name, overlap=overlap):
                    grain = [pairStiffness(n, u, overlap, 'grain') for n in (10, 30, 70)]
                    K = [k for k, p in grain]
                    self.assertLessEqual(max(K) / min(K), 1.5, (K, [p for k, p in grain]))
        spheres = [pairStiffness(n, (0, 1, 0), 0.02, 'spheres')[0] for n in (10, 70)]
        self.assertGreater(spheres[1] / spheres[0], 5)  # YADE's own: 9x here (the problem)

    def test_one_contact_is_one_grain_contact(self):
        # tip to tip the first contact alone: the grains' own stiffness, 2 E R1 R2 / (R1 + R2) = E R
        k, pairs = pairStiffness(10, (1, 0, 0), 0.002, 'grain')
        self.assertEqual(pairs, 1)
        R = (3 * result(10).targetMass.volume / (4 * np.pi)) ** (1 / 3)
        self.assertAlmostEqual(k / (1e8 * R), 1.0, delta=0.02)  # the overlap measured from the first touch


class Sliding(unittest.TestCase):
    def test_a_sliding_pair_carries_mu_times_its_normal_force(self):
        # side to side at 2 %, the upper clump dragged along x: every member contact at its Coulomb limit, so the
        # pair's shear force is tan(phi) times its normal force, as one contact of the grains would carry
        pairStiffness(30, (0, 1, 0), 0.02, 'grain')
        moving = [b for b in O.bodies if b.isClump][1]
        moving.state.vel = (100.0, 0, 0)  # 0.2 of a length in 2000 steps: each contact past its elastic share
        O.run(2000, True)
        fn, fs = np.zeros(3), np.zeros(3)
        for i in O.interactions:
            if i.isReal:
                n, s_ = np.array(i.phys.normalForce), np.array(i.phys.shearForce)
                self.assertLessEqual(np.linalg.norm(s_), np.tan(0.5) * np.linalg.norm(n) * (1 + 1e-9))
                fn, fs = fn + n, fs + s_
        self.assertAlmostEqual(np.linalg.norm(fs) / np.linalg.norm(fn), np.tan(0.5), delta=0.02 * np.tan(0.5))


class Default(unittest.TestCase):
    def test_spheres_is_yades_own(self):
        O.reset()
        mat = O.materials.append(FrictMat(young=1e8, poisson=0.3, frictionAngle=0.5, density=2000))  # noqa: F405
        a, am = mssClump(result(10), material=mat, fixed=True)
        self.assertFalse(O.bodies[am[0]].material.label.endswith(GRAIN_STIFFNESS_MARK))
        self.assertIs(O.bodies[am[0]].material, O.materials[mat])
        with self.assertRaises(ValueError) as e:
            mssClump(result(10), material=mat, contactStiffness='grains')
        self.assertIn('contactStiffness', str(e.exception))


class Survives(unittest.TestCase):
    def test_save_load_restore_and_every_builder(self):
        O.reset()
        mat = O.materials.append(FrictMat(young=1e8, poisson=0.3, frictionAngle=0.5, density=2000,  # noqa: F405
                                          label='rock'))
        mssClump(result(10), material=mat, contactStiffness='grain')
        t = mssTemplate(result(10))
        mssClumpCloud([t], (10, 0, 0), (20, 10, 10), num=3, seed=1, material=mat, contactStiffness='grain')
        O.bodies.append(utils.sphere((50, 0, 0), 2.0, material=mat))
        mssReplaceByClumps([t], [1.0], seed=1, material=mat, contactStiffness='grain')
        marked = lambda: [b.id for b in O.bodies if b.isClump and O.bodies[  # noqa: E731
            list(b.shape.members.keys())[0]].material.label == 'rock' + GRAIN_STIFFNESS_MARK]
        self.assertEqual(len(marked()), 5)
        self.assertEqual(sum(1 for m in O.materials if m.label.endswith(GRAIN_STIFFNESS_MARK)), 1)  # one twin
        O.bodies.updateClumpProperties(discretization=0)
        restoreClumpProperties()
        self.assertEqual(len(marked()), 5)
        O.engines = engines('grain')
        folder = tempfile.mkdtemp()
        try:
            O.save(os.path.join(folder, 's.yade.gz'))
            O.reset()
            O.load(os.path.join(folder, 's.yade.gz'))
        finally:
            shutil.rmtree(folder)
        self.assertEqual(len(marked()), 5)
        self.assertIn('contactStiffnessStep', ' '.join(getattr(e, 'command', '') for e in O.engines))
        labels = np.zeros((30, 30, 30), np.int32)
        labels[2:12, 2:12, 2:12] = 1
        got = mssAssembly(labels, voxelSize=1.0, origin=(100, 0, 0), nSpheres=4, material=mat,
                          contactStiffness='grain')
        self.assertEqual(len(marked()), 6)
        self.assertEqual(len(got), 1)

    def test_the_pieces_of_a_broken_clump_keep_it(self):
        O.reset()
        mat = O.materials.append(FrictMat(young=1e8, poisson=0.3, frictionAngle=0.5, density=2000))  # noqa: F405
        cid, ids = mssClump(ELL, nSpheres=10, material=mat, breakable=True, contactStiffness='grain')
        pieces = mssSplit(cid, ((0, 0, 0), (1, 0, 0)), nSpheres=6)
        self.assertGreaterEqual(len(pieces), 2)
        for pc, pm in pieces:
            self.assertTrue(O.bodies[pm[0]].material.label.endswith(GRAIN_STIFFNESS_MARK))


class Settles(unittest.TestCase):
    def test_a_packing_settles_with_it(self):
        # each contact a linear spring once set: nothing is pumped into the motion, the packing comes to rest
        O.reset()
        mat = O.materials.append(FrictMat(young=1e7, poisson=0.3, frictionAngle=0.5, density=2000))  # noqa: F405
        O.bodies.append(utils.wall(0, axis=2, sense=1, material=mat))
        mssClumpCloud([mssTemplate(result(10))], (-4, -4, 1), (4, 4, 8), num=8, seed=3, material=mat,
                      contactStiffness='grain')
        O.engines = engines('grain')
        O.engines[-1].gravity = (0, 0, -9.81)
        O.engines[-1].damping = 0.4
        O.dt = 0.5 * utils.PWaveTimeStep()
        O.run(20000, True)
        self.assertLess(utils.unbalancedForce(), 0.05)
        # at rest: the kinetic energy is under 1e-5 of the clumps' weight times a grain's size (a still packing)
        d = 2 * (3 * result(10).targetMass.volume / (4 * np.pi)) ** (1 / 3)
        weight = sum(b.state.mass for b in O.bodies if b.isClump) * 9.81
        self.assertLess(utils.kineticEnergy(), 1e-5 * weight * d)


if __name__ == '__main__':
    result_ = unittest.main(exit=False, verbosity=2).result
    print('%d passed, %d failed' % (result_.testsRun - len(result_.failures) - len(result_.errors),
                                   len(result_.failures) + len(result_.errors)))
    sys.exit(0 if result_.wasSuccessful() else 1)
