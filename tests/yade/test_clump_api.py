"""YADE's clump API on mssClump clumps, side by side with a plain appendClumped clump of the same spheres.
Run: yade -n -x tests/yade/test_clump_api.py"""
import glob
import inspect
import math
import os
import sys
import tempfile
import unittest
import warnings

import numpy as np

sys.path.insert(0, os.path.join(os.environ.get('MSS_TEST_DATA', 'tests/data'), '..', 'yade'))
from clumptools import ELL, FEMUR, ballSums, meshMass, readStlTriangles, relErr, rot, tensor, unionByGrid, vec  # noqa: E402

from yade import utils, export, ymport  # noqa: E402
from yade.wrapper import *  # noqa: F401,F403,E402
import yade.minieigenHP as me  # noqa: E402

import yade_mss  # noqa: E402
from yade_mss import generate, mssClump, restoreClumpProperties, readClumps, writeClumps  # noqa: E402

O = Omega()
RHO = 2000.0
_femur = []


def femur20():
    if not _femur:
        _femur.append(generate(FEMUR, nSpheres=20, resolution=50))
    return _femur[0]


def exactFemur():
    V, c, I = meshMass(readStlTriangles(FEMUR))
    return RHO * V, c, RHO * I


class Base(unittest.TestCase):
    def setUp(self):
        O.reset()
        self.mat = O.materials.append(FrictMat(density=RHO, young=1e7, poisson=0.3, frictionAngle=0.5, label='grain'))

    def pair(self, r=None, shift=(300, 0, 0)):
        """Our clump of result r and a plain appendClumped clump of the same spheres, shifted."""
        r = r or femur20()
        ours = mssClump(r, material=self.mat)
        plain = O.bodies.appendClumped([utils.sphere(tuple(c + np.array(shift)), float(rad), material=self.mat)
                                        for c, rad in zip(r.centers, r.radii)])
        return ours, plain

    def assertExact(self, cid, M, C, I, tol=1e-9):
        st = O.bodies[cid].state
        self.assertLess(abs(st.mass - M) / M, tol)
        self.assertLess(np.linalg.norm(vec(st.pos) - C) / 100.0, tol)
        self.assertLess(relErr(tensor(st), I), 100 * tol)

    def members(self, cid):
        return sorted(O.bodies[cid].shape.members.keys())

    def assertUnionOfMembers(self, cid, h, tol):
        """The clump carries the mass properties of the union of its present members (numpy grid of step h)."""
        m = self.members(cid)
        c = np.array([vec(O.bodies[i].state.pos) for i in m])
        rad = np.array([O.bodies[i].shape.radius for i in m])
        V, cen, I = unionByGrid(c, rad, h)
        self.assertExact(cid, RHO * V, cen, RHO * I, tol=tol)


class Exact(Base):
    def test_members_are_exactly_the_spheres(self):
        r = femur20()
        (cid, ids), _ = self.pair()
        self.assertEqual(self.members(cid), sorted(ids))
        self.assertEqual(len(ids), len(r))
        # the idiom users write works on every member
        radii = [O.bodies[i].shape.radius for i in O.bodies[cid].shape.members]
        self.assertEqual(sorted(radii), sorted(r.radii.tolist()))

    def test_grain_mass_properties_against_independent_sums(self):
        (cid, ids), _ = self.pair()
        M, C, I = exactFemur()
        self.assertExact(cid, M, C, I)
        # the body frame is the principal frame: the tensor in it is diagonal (YADE stores three moments)
        R = rot(O.bodies[cid].state.ori)
        D = R.T.dot(I).dot(R)
        self.assertLess(np.abs(D - np.diag(np.diag(D))).max() / np.abs(D).max(), 1e-9)

    def test_members_carry_their_own_sphere_mass(self):
        # the bug: members carried 0.17-0.34 of rho V (femur), which YADE's laws and time steps read
        (cid, ids), (pc, pids) = self.pair()
        for i, j in zip(ids, pids):
            a, b = O.bodies[i], O.bodies[j]
            V = 4.0 / 3.0 * math.pi * a.shape.radius ** 3
            self.assertEqual(a.state.mass, b.state.mass)  # bit for bit what appendClumped's members carry
            self.assertLess(abs(a.state.mass / (RHO * V) - 1), 1e-14)
            self.assertEqual(vec(a.state.inertia).tolist(), vec(b.state.inertia).tolist())
        # utils.getSpheresMass() sums members (overlaps twice) for both alike; totalMass() is the clumps'
        from yade_mss import totalMass
        self.assertLess(abs(utils.getSpheresMass() - 2 * sum(O.bodies[i].state.mass for i in ids)), 1e-9)
        total = O.bodies[cid].state.mass + O.bodies[pc].state.mass
        self.assertLess(abs(totalMass() - total) / total, 1e-15)

    def test_union_mass_for_overlapping_spheres(self):
        r = generate(ELL, nSpheres=10, resolution=60)
        cid, ids = mssClump(r, mass='union')
        V, c, I = unionByGrid(r.centers, r.radii, 0.01)
        self.assertExact(cid, RHO * V, c, RHO * I, tol=0.005)


class SideBySide(Base):
    def test_release_down_to_two_members(self):
        # the bug: releases drove the mass negative and the fourth aborted YADE (Clump.cpp:241 'M > 0')
        r = generate(ELL, nSpheres=10, resolution=103)
        (cid, ids), (pc, pids) = self.pair(r)
        for k in range(len(ids) - 2):
            O.bodies.releaseFromClump(ids[k], cid)
            O.bodies.releaseFromClump(pids[k], pc)
            self.assertEqual(len(self.members(cid)), len(ids) - k - 1)
            # YADE recomputes both from the remaining spheres alike
            a, b = O.bodies[cid].state, O.bodies[pc].state
            self.assertGreater(a.mass, 0)
            self.assertLess(abs(a.mass - b.mass) / b.mass, 1e-12)
            self.assertLess(relErr(tensor(a), tensor(b)), 1e-9)
        # the released spheres are free bodies with positive mass
        self.assertTrue(all(O.bodies[i].state.mass > 0 and not O.bodies[i].isClumpMember for i in ids[:-2]))
        # restoring gives the union of the two left, overlaps once
        self.assertEqual(restoreClumpProperties([cid]), [(cid, 'union')])
        self.assertUnionOfMembers(cid, 0.005, 0.005)

    def test_add_to_clump(self):
        (cid, ids), (pc, pids) = self.pair()
        extra = [O.bodies.append(utils.sphere(tuple(vec(O.bodies[b].state.pos) + (5, 0, 0)), 8.0, material=self.mat))
                 for b in (ids[0], pids[0])]
        O.bodies.addToClump([extra[0]], cid)
        O.bodies.addToClump([extra[1]], pc)
        self.assertEqual(len(self.members(cid)), len(ids) + 1)
        self.assertLess(abs(O.bodies[cid].state.mass / O.bodies[pc].state.mass - 1), 1e-12)
        self.assertEqual(restoreClumpProperties([cid]), [(cid, 'union')])
        self.assertUnionOfMembers(cid, 0.5, 0.01)

    def test_erase_keeps_free_spheres_of_positive_mass(self):
        (cid, ids), (pc, pids) = self.pair()
        O.bodies.erase(cid)
        O.bodies.erase(pc)
        for i, j in zip(ids, pids):
            b = O.bodies[i]
            self.assertFalse(b.isClumpMember)
            self.assertEqual(b.state.mass, O.bodies[j].state.mass)  # rho V, as a sphere freed by YADE
            self.assertEqual(vec(b.state.inertia).tolist(), vec(O.bodies[j].state.inertia).tolist())
        O.engines = [ForceResetter(), NewtonIntegrator(damping=0, gravity=(0, 0, -9.81))]
        O.dt = 1e-3
        O.run(100, True)
        ek = utils.kineticEnergy()
        self.assertTrue(math.isfinite(ek) and ek > 0)
        # free fall: every sphere moves at g t, nothing falls faster or stays behind
        for i in ids + pids:
            self.assertAlmostEqual(O.bodies[i].state.vel[2], -9.81 * 0.1, places=9)

    def test_erase_with_members(self):
        (cid, ids), (pc, pids) = self.pair()
        O.bodies.erase(cid, True)
        O.bodies.erase(pc, True)
        self.assertEqual(len([b for b in O.bodies if b is not None]), 0)
        self.assertEqual(restoreClumpProperties(), [])  # the erased clump is forgotten

    def test_update_clump_properties_then_restore(self):
        (cid, ids), (pc, pids) = self.pair()
        M, C, I = exactFemur()
        r = femur20()
        for disc in (0, 5, 10):
            O.bodies.updateClumpProperties(discretization=disc)
            a, b = O.bodies[cid].state, O.bodies[pc].state
            self.assertLess(abs(a.mass - b.mass) / b.mass, 1e-12)  # YADE treats both alike
            if disc == 0:  # overlaps counted twice, for both
                Mb, Cb, Ib = ballSums(r.centers, r.radii, RHO)
                self.assertLess(abs(a.mass - Mb) / Mb, 1e-12)
            self.assertEqual(restoreClumpProperties(), [(cid, 'grain')])
            self.assertExact(cid, M, C, I)

    def test_grown_particles_keep_their_exact_properties(self):
        # utils.growParticles, YADE's usual way to densify, grows both clumps about their centres alike; ours keeps
        # its record (grown with it): the restore gives the grown grain's exact mass (s^3) and inertia (s^5), after
        # YADE's own update too (the record was dropped as "made for another clump", then the mass lost for good)
        (cid, ids), (pc, pids) = self.pair()
        M, C, I = exactFemur()
        for s in (1.1, 0.95):
            plain = O.bodies[pc].state.mass
            utils.growParticles(s)
            self.assertLess(abs(O.bodies[pc].state.mass / plain - s ** 3), 1e-9)  # YADE's clump, as it grows
            M, I = M * s ** 3, I * s ** 5
            with warnings.catch_warnings():
                warnings.simplefilter('error')  # no record dropped
                self.assertEqual(restoreClumpProperties(), [(cid, 'grain')])
            self.assertExact(cid, M, C, I)
            O.bodies.updateClumpProperties(discretization=0)  # YADE's sums: overlaps counted twice
            self.assertGreater(O.bodies[cid].state.mass, 1.5 * M)
            self.assertEqual(restoreClumpProperties(), [(cid, 'grain')])
            self.assertExact(cid, M, C, I)

    def test_clumps_placed_alike_share_record_parts_and_restore_exactly(self):
        # a record's parts besides the member ids are kept per turn and scale of a placement: clumps placed alike
        # (a cache hit), turned (a miss) or scaled must each carry a record of their own members, as encodeMany
        # writes it from scratch (to rounding: the kept parts were computed at another place), and each restore
        # its own exact properties
        from yade_mss.yade import _records
        from yade_mss.yade._clumps import _basePlan
        r = femur20()
        M, C, I = exactFemur()
        a = np.array([1.0, 2.0, 3.0]) / math.sqrt(14.0)
        K = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
        R = np.eye(3) + math.sin(0.7) * K + (1 - math.cos(0.7)) * K.dot(K)
        placed = [((0, 0, 0), None, 1.0), ((300, 0, 0), None, 1.0), ((0, 300, 0), R, 1.0), ((0, 0, 300), R, 1.0),
                  ((300, 300, 0), None, 0.5), ((300, 0, 300), None, 0.5)]
        made = [mssClump(r, center=c, orientation=o, scale=s, material=self.mat) for c, o, s in placed]
        base, c0 = _basePlan(r, 'target')
        for (cid, ids), (c, o, s) in zip(made, placed):
            q = base.placed(c0, s, np.eye(3) if o is None else R, np.array(c, dtype=float))
            want = _records.Record(_records.encodeMany(
                [ids], [q.centers], [q.radii], np.array([q.volume]), np.array([q.centroid]), np.array([q.inertia]),
                [q.m], np.array([q.V]), np.array([q.j]), np.array([np.eye(3)]))[0])
            got = _records.Record(O.bodies[cid].material.label)
            self.assertEqual(list(got.ids), list(ids))
            for f in ('volume', 'centroid', 'inertia', 'J', 'radii', 'rel', 'm'):
                g, w = np.asarray(getattr(got, f), dtype=float), np.asarray(getattr(want, f), dtype=float)
                self.assertLessEqual(np.abs(g - w).max(), 1e-12 * max(1.0, np.abs(w).max()), f)
            self.assertLess(np.abs(np.array([vec(O.bodies[i].state.pos) for i in ids]) - q.centers).max(), 1e-9)
        O.bodies.updateClumpProperties(discretization=0)
        self.assertEqual(sorted(restoreClumpProperties()), sorted((cid, 'grain') for cid, ids in made))
        for (cid, ids), (c, o, s) in zip(made, placed):
            Rk = np.eye(3) if o is None else R
            self.assertExact(cid, s ** 3 * M, np.array(c, dtype=float), s ** 5 * Rk.dot(I).dot(Rk.T))

    def test_density_change_then_update_and_restore(self):
        (cid, ids), (pc, pids) = self.pair()
        M, C, I = exactFemur()
        O.materials[self.mat].density /= 10
        for i in ids + pids:
            O.bodies[i].state.mass /= 10
        O.bodies.updateClumpProperties(discretization=0)  # aborted YADE before
        a, b = O.bodies[cid].state, O.bodies[pc].state
        self.assertLess(abs(a.mass - b.mass) / b.mass, 1e-12)
        restoreClumpProperties()
        self.assertExact(cid, M / 10, C, I / 10)
        for i in ids:  # members follow the density: YADE's spheres of it
            b = O.bodies[i]
            self.assertLess(abs(b.state.mass / (RHO / 10 * 4.0 / 3.0 * math.pi * b.shape.radius ** 3) - 1), 1e-14)

    def test_turned_clumps_restore_exactly_again_and_again(self):
        # the record is in member 1's frame, which only turns with the clump: after the clump turned, restores
        # stay exact, and one of an unchanged clump writes nothing (member 0's frame is set again each time)
        (cid, ids), _ = self.pair()
        r1 = generate(FEMUR, nSpheres=1, resolution=30)
        with warnings.catch_warnings():  # one sphere: the centre of mass off it is said, and moved onto it
            warnings.simplefilter('ignore')
            one, oneIds = mssClump(r1, material=self.mat, center=(0, 300, 0))
        M, C, I = exactFemur()
        x0, x1 = vec(O.bodies[ids[0]].state.pos), vec(O.bodies[oneIds[0]].state.pos)
        c1, I1 = O.bodies[one].state.pos, tensor(O.bodies[one].state)
        c1 = vec(c1)
        label = O.bodies[cid].material.label
        O.engines = [ForceResetter(), NewtonIntegrator(damping=0, gravity=(0, 0, 0))]
        O.dt = 1e-3
        for turn in range(3):
            for k in (cid, one):  # a clump moves by its angular momentum
                st = O.bodies[k].state
                w = np.array([0.7, -0.4 * turn, 1.1])
                st.angVel, st.angMom = me.Vector3(*w), me.Vector3(*tensor(st).dot(w))
            O.run(400, True)
            O.bodies.updateClumpProperties(discretization=0)
            self.assertEqual(sorted(restoreClumpProperties()), sorted([(cid, 'grain'), (one, 'grain')]))
            self.assertEqual(O.bodies[cid].material.label, label)  # nothing written for it
            R = rot(O.bodies[ids[1]].state.ori)  # member 1 started unturned
            self.assertGreater(np.linalg.norm(R - np.eye(3)), 0.5)  # it did turn
            self.assertExact(cid, M, vec(O.bodies[ids[0]].state.pos) + R.dot(C - x0), R.dot(I).dot(R.T))
            # a lone member: its record is in member 0's frame, written again; mass, principal moments and the
            # centre's distance from the sphere are those it was made with
            st = O.bodies[one].state
            self.assertLess(abs(st.mass - RHO * r1.targetMass.volume) / st.mass, 1e-9)
            np.testing.assert_allclose(np.linalg.eigvalsh(tensor(st)), np.linalg.eigvalsh(I1), rtol=1e-9,
                                       atol=1e-12 * np.abs(I1).max())
            self.assertAlmostEqual(np.linalg.norm(vec(st.pos) - vec(O.bodies[oneIds[0]].state.pos)),
                                   np.linalg.norm(c1 - x1), delta=1e-9 * 100)

    def test_restore_keeps_the_motion(self):
        (cid, ids), _ = self.pair()
        st = O.bodies[cid].state
        st.vel = me.Vector3(1, 2, 3)
        st.angVel = me.Vector3(0.1, -0.2, 0.3)
        O.bodies.updateClumpProperties(discretization=0)
        self.assertEqual(vec(st.vel).tolist(), [0, 0, 0])  # YADE's update stops a clump
        st.vel, st.angVel = me.Vector3(1, 2, 3), me.Vector3(0.1, -0.2, 0.3)
        p0 = vec(st.pos)
        restoreClumpProperties()
        w = np.array([0.1, -0.2, 0.3])
        np.testing.assert_allclose(vec(st.angVel), w, rtol=1e-12)
        np.testing.assert_allclose(vec(st.vel), np.array([1, 2, 3]) + np.cross(w, vec(st.pos) - p0), rtol=1e-9)
        np.testing.assert_allclose(vec(st.angMom), tensor(st).dot(w), rtol=1e-9)

    def test_save_load_and_tmp(self):
        (cid, ids), (pc, pids) = self.pair()
        M, C, I = exactFemur()
        with tempfile.TemporaryDirectory() as d:
            f = os.path.join(d, 'scene.yade.gz')
            O.save(f)
            O.reset()
            O.load(f)
            self.assertExact(cid, M, C, I)
            self.assertEqual(len(self.members(cid)), len(ids))
            O.bodies.updateClumpProperties(discretization=0)
            self.assertEqual(restoreClumpProperties(), [(cid, 'grain')])  # the record travels with the scene
            self.assertExact(cid, M, C, I)
        O.saveTmp('t')
        O.bodies.updateClumpProperties(discretization=0)
        O.loadTmp('t')
        self.assertExact(cid, M, C, I)

    def test_vtk_recorder_and_exporter(self):
        (cid, ids), (pc, pids) = self.pair()
        with tempfile.TemporaryDirectory() as d:
            # every recorder but 'intr' (so not 'all'): in YADE 2023.02a here it never returns, plain scenes too
            recorders = ['spheres', 'facets', 'boxes', 'colors', 'mask', 'ids', 'mass', 'clumpId', 'materialId',
                         'velocity', 'stress', 'force']
            O.engines = [ForceResetter(), VTKRecorder(fileName=os.path.join(d, 'rec-'), recorders=recorders,
                                                      iterPeriod=1), NewtonIntegrator(gravity=(0, 0, 0))]
            O.dt = 1e-4
            O.run(1, True)
            files = sorted(os.path.basename(f) for f in glob.glob(os.path.join(d, '*')))
            self.assertTrue(any('spheres' in f for f in files), files)
            boxes = open(glob.glob(os.path.join(d, '*boxes*'))[0]).read()  # written, but empty: no helper body
            self.assertIn('NumberOfCells="0"', boxes)
            spheres = open(glob.glob(os.path.join(d, '*spheres*'))[0]).read()
            self.assertIn('NumberOfPoints="%d"' % (len(ids) + len(pids)), spheres)
            ex = export.VTKExporter(os.path.join(d, 'exp'))
            ex.exportSpheres(what=dict(mass='b.state.mass'))
            text = open(glob.glob(os.path.join(d, 'exp*'))[0]).read()
            self.assertIn('POINTS %d' % (len(ids) + len(pids)), text)

    def test_text_clumps_round_trip(self):
        (cid, ids), (pc, pids) = self.pair()
        M, C, I = exactFemur()
        with tempfile.TemporaryDirectory() as d:
            f = os.path.join(d, 'c.txt')
            export.textClumps(f)
            O.bodies.clear()
            back = ymport.textClumps(f, material=self.mat)
            self.assertEqual(len(back), 2)
            # YADE's own reader sums the spheres again, for both alike
            self.assertLess(abs(O.bodies[back[0][0]].state.mass / O.bodies[back[1][0]].state.mass - 1), 1e-6)
            # ours keeps the exact properties
            O.reset()
            self.mat = O.materials.append(FrictMat(density=RHO, label='grain'))
            (cid, ids), (pc, pids) = self.pair()
            n = writeClumps(f)
            self.assertEqual(n, (2, 2 * len(ids)))
            plainMass = O.bodies[pc].state.mass
            O.reset()
            heavy = O.materials.append(FrictMat(density=2 * RHO))
            back = readClumps(f, material=heavy)
            self.assertEqual(len(back), 2)
            self.assertExact(back[0][0], 2 * M, C, 2 * I)  # scaled to the density used when reading
            self.assertLess(abs(O.bodies[back[1][0]].state.mass / (2 * plainMass) - 1), 1e-12)
            # YADE's reader takes our file too (the '#mss' lines are comments to it)
            O.reset()
            O.materials.append(FrictMat(density=RHO))
            self.assertEqual(len(ymport.textClumps(f)), 2)

    def test_exported_clumps_file(self):
        """mss export --format yade: readClumps builds the grain with its exact mass properties (at the material's
        density), in the template's frame; YADE's ymport.textClumps reads the same spheres."""
        r = femur20()
        M, C, I = exactFemur()
        w, R = np.linalg.eigh(I)
        with tempfile.TemporaryDirectory() as d:
            for frame in ('principal', 'generated'):
                f = os.path.join(d, frame + '.txt')
                r.export(f, format='yade', density=1.0, frame=frame)
                O.reset()
                mat = O.materials.append(FrictMat(density=RHO))
                (cid, ids), = readClumps(f, material=mat)
                st = O.bodies[cid].state
                self.assertLess(abs(st.mass - M) / M, 1e-9)
                self.assertLess(np.linalg.norm(vec(st.pos)), 1e-9 * 100)  # the centre of mass at the origin
                # the world tensor it simulates with: the grain's, in the file's axes
                J = tensor(st)
                if frame == 'principal':
                    np.testing.assert_allclose(np.sort(np.diag(J)), np.sort(w), rtol=1e-8)
                    self.assertLess(np.abs(J - np.diag(np.diag(J))).max(), 1e-8 * w.max())
                else:
                    self.assertLess(relErr(J, I), 1e-8)
                self.assertEqual(len(ids), len(r))
                O.reset()
                O.materials.append(FrictMat(density=RHO))
                self.assertEqual(len(ymport.textClumps(f)), 1)
                self.assertEqual(len([b for b in O.bodies if b.isClumpMember]), len(r))

    def test_periodic_cell(self):
        O.periodic = True
        O.cell.hSize = Matrix3(500, 0, 0, 0, 500, 0, 0, 0, 500)
        (cid, ids), (pc, pids) = self.pair(shift=(200, 0, 0))
        M, C, I = exactFemur()
        O.engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb()]),
                     InteractionLoop([Ig2_Sphere_Sphere_ScGeom()], [Ip2_FrictMat_FrictMat_FrictPhys()],
                                     [Law2_ScGeom_FrictPhys_CundallStrack()]),
                     NewtonIntegrator(gravity=(0, 0, 0))]
        O.bodies[cid].state.vel = me.Vector3(1000, 0, 0)  # it crosses the cell's face
        O.dt = 1e-3
        O.run(400, True)
        st = O.bodies[cid].state
        self.assertLess(abs(st.mass - M) / M, 1e-12)
        self.assertLess(relErr(tensor(st), rot(st.ori).dot(rot(st.ori).T).dot(tensor(st))), 1e-12)
        self.assertGreater(st.pos[0], C[0] + 350)
        self.assertEqual(restoreClumpProperties(), [(cid, 'grain')])
        self.assertLess(abs(O.bodies[cid].state.mass - M) / M, 1e-9)


class EveryName(unittest.TestCase):
    """Every public name that needs YADE, every keyword argument of it given a value of the wrong kind: a
    TypeError or ValueError naming the argument (the names without YADE: tests/python/base/test_every_name.py)."""

    def setUp(self):
        O.reset()
        O.materials.append(FrictMat(density=RHO, young=1e7, poisson=0.3, frictionAngle=0.5))
        yade_mss.mssClump(ELL, nSpheres=4, resolution=20)

    def test_every_keyword_of_the_wrong_kind_is_refused_by_name(self):
        d = tempfile.mkdtemp()
        template = yade_mss.mssTemplate(ELL, nSpheres=3, resolution=20)
        labels = os.path.join(os.path.dirname(ELL), 'two_grains_labels.npy')
        calls = {  # a valid call's arguments (made in a fresh scene) and keywords
            'mssClump': (lambda: (ELL,), dict(nSpheres=3, resolution=20)),
            'restoreClumpProperties': (lambda: (), {}),
            'porosity': (lambda: (), {}),
            'writeClumps': (lambda: (os.path.join(d, 'c.txt'),), {}),
            'mssTemplate': (lambda: (ELL,), dict(nSpheres=3, resolution=20)),
            'mssClumpCloud': (lambda: ([template], (0, 0, 0), (10, 10, 10)), dict(num=2, seed=1)),
            'mssReplaceByClumps': (lambda: ([template], [1.0]), {}),
            'mssAssembly': (lambda: (labels,), dict(nSpheres=3, voxelSize=1e-3)),
            'grainSizes': (lambda: (), {}),
            'contactStiffnessEngine': (lambda: (), {}),
            'MssBreakage': (lambda: (), dict(sigma0=1e6, d0=1e-3)),
            'mssSplit': (lambda: (yade_mss.mssClump(ELL, nSpheres=4, resolution=20, breakable=True)[0],
                                  ((0, 0, 0), (1, 0, 0))), dict(nSpheres=2)),
            'triaxial': (lambda: ([template],), dict(grains=10, strain=0.001)),
        }
        # the names of tests/python/base/test_every_name.py's YADE set: each called here, or taking no keyword
        # with a default (totalMass, breakageLog; readClumps: YADE's body keywords), or checked by its own
        # test before any work (triaxialStudy: tests/python/studies)
        self.assertEqual(set(calls) | {'totalMass', 'breakageLog', 'readClumps', 'triaxialStudy'},
                         {'mssClump', 'restoreClumpProperties', 'totalMass', 'porosity', 'writeClumps', 'readClumps',
                          'mssTemplate', 'mssClumpCloud', 'mssReplaceByClumps', 'mssAssembly', 'mssSplit',
                          'MssBreakage', 'breakageLog', 'grainSizes', 'contactStiffnessEngine', 'triaxial',
                          'triaxialStudy'})
        for name, (args, kw) in calls.items():
            f = getattr(yade_mss, name)
            for p in inspect.signature(f).parameters.values():
                if p.default is inspect.Parameter.empty or p.kind in (p.VAR_KEYWORD, p.VAR_POSITIONAL):
                    continue
                bads = (['no', 1.5] if isinstance(p.default, bool) else ['abc', [1]]
                        if isinstance(p.default, (int, float)) else [object()])
                for bad in bads:
                    with self.subTest('%s(%s=%r)' % (name, p.name, bad)):
                        self.setUp()
                        if name == 'triaxial':
                            O.reset()  # it builds its own specimen
                        if name == 'mssReplaceByClumps':
                            O.bodies.append(utils.sphere((0, 0, 0), 1.0))
                        with self.assertRaises((TypeError, ValueError)) as ctx:
                            f(*args(), **dict(kw, **{p.name: bad}))
                        self.assertIn(p.name, str(ctx.exception))


if __name__ == '__main__':
    result = unittest.main(exit=False, verbosity=2).result
    print('%d passed, %d failed' % (result.testsRun - len(result.failures) - len(result.errors),
                                   len(result.failures) + len(result.errors)))
    sys.exit(0 if result.wasSuccessful() else 1)
