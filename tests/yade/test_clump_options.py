"""mssClump, mssTemplate, mssClumpCloud, mssReplaceByClumps: strict keywords, bad input, packing helpers.
Run: yade -n -x tests/yade/test_clump_options.py"""
import math
import os
import sys
import unittest

import numpy as np

sys.path.insert(0, os.path.join(os.environ.get('MSS_TEST_DATA', 'tests/data'), '..', 'yade'))
from clumptools import DATA, ELL, FEMUR, rot, vec  # noqa: E402

from yade import utils, pack  # noqa: E402
from yade.wrapper import *  # noqa: F401,F403,E402
import yade.minieigenHP as me  # noqa: E402

from yade_mss import (generate, mssClump, mssTemplate, mssClumpCloud, mssReplaceByClumps,  # noqa: E402
                      restoreClumpProperties)

O = Omega()
LABELS = os.path.join(DATA, 'two_grains_labels.npy')
GRAIN = os.path.join(DATA, 'grain_voxels_155x157x167.npy')


def smallestGap(clumps):
    """The least distance between spheres of two different clumps (negative: they overlap)."""
    members = [(np.array([vec(O.bodies[i].state.pos) for i in ids]), np.array([O.bodies[i].shape.radius for i in ids]))
               for cid, ids in clumps]
    gap = np.inf
    for a in range(len(members)):
        for b in range(a):
            d = (np.linalg.norm(members[a][0][:, None] - members[b][0][None], axis=2) - members[a][1][:, None]
                 - members[b][1][None])
            gap = min(gap, d.min())
    return gap


class Base(unittest.TestCase):
    def setUp(self):
        O.reset()
        self.mat = O.materials.append(FrictMat(density=2000, young=1e7, poisson=0.3, frictionAngle=0.5, label='grain'))


class Keywords(Base):
    def test_typo_names_the_closest_keyword_before_generating(self):
        # a missing file would be a ValueError: the TypeError proves nothing was read or generated
        for func, kw, near in ((mssClump, 'nSphere', 'nSpheres'), (mssClump, 'colour', 'color'),
                               (mssClump, 'resolutoin', 'resolution'), (mssTemplate, 'nsphere', 'nSpheres'),
                               (mssClumpCloud, 'materail', 'material')):
            with self.subTest(kw):
                args = ([('missing.stl')], (0, 0, 0), (1, 1, 1)) if func is mssClumpCloud else ('missing.stl',)
                with self.assertRaises(TypeError) as ctx:
                    func(*args, **{kw: 3})
                self.assertIn("'%s'" % kw, str(ctx.exception))
                self.assertIn("did you mean '%s'?" % near, str(ctx.exception))
        self.assertEqual(len(O.bodies), 0)

    def test_every_generate_option_by_name(self):
        planes = [((0, 0, -0.5), (0, 0, 1))]
        cid, ids = mssClump(ELL, nSpheres=6, resolution=30, method='paper', supersample=2, threads=1,
                            memoryLimit=1, maxIterations=50, deltaMin=1.0, keepSymmetry=False, planes=planes,
                            clip=True, refill=True, material=self.mat)
        self.assertGreater(len(ids), 0)
        for i in ids:  # clipped and above the plane
            b = O.bodies[i]
            self.assertGreaterEqual(b.state.pos[2] - b.shape.radius, -0.5 - 1e-9)
        a = np.zeros((20, 20, 20), dtype=np.int32)
        a[4:16, 4:16, 4:10] = 7
        cid, ids = mssClump(a, label=7, voxelSize=0.5, origin=(1, 2, 3), nSpheres=4, rMin=0.1)
        st = O.bodies[cid].state
        np.testing.assert_allclose(vec(st.pos), np.array([1, 2, 3]) + 0.5 * np.array([9.5, 9.5, 6.5]), atol=1e-9)

    def test_body_options_by_name(self):
        cid, ids = mssClump(ELL, nSpheres=4, resolution=30, material='grain', color=(0, 1, 0), mask=5, fixed=True,
                            wire=True, highlight=True)
        for i in ids:
            b = O.bodies[i]
            self.assertEqual(tuple(b.shape.color), (0, 1, 0))
            self.assertEqual(b.mask, 5)
            self.assertTrue(b.shape.wire and b.shape.highlight)
            self.assertFalse(b.dynamic)

    def test_generation_options_with_a_result_are_refused(self):
        r = generate(ELL, nSpheres=4, resolution=30)
        with self.assertRaises(ValueError) as ctx:
            mssClump(r, nSpheres=8)
        self.assertIn('nSpheres', str(ctx.exception))
        self.assertEqual(len(O.bodies), 0)


class BadInput(Base):
    def test_labelled_volume_needs_a_label(self):
        for src in (LABELS, np.load(LABELS)):
            with self.assertRaises(ValueError) as ctx:
                mssClump(src, nSpheres=4, voxelSize=1e-3)
            self.assertIn('labels (1, 2)', str(ctx.exception))
        self.assertEqual(len(O.bodies), 0)
        cid, ids = mssClump(LABELS, label=2, nSpheres=4, voxelSize=1e-3)
        self.assertEqual(len(ids), 4)

    def test_a_volume_without_its_voxel_size_is_refused(self):
        # the bug: a voxel was taken as 1 m: mssClump of the bundled CT grain made a 3.06e9 kg grain without a word
        from yade_mss import mssAssembly
        for call in (lambda: mssClump(GRAIN, nSpheres=4), lambda: mssClump(np.load(LABELS), label=1, nSpheres=4),
                     lambda: mssTemplate(GRAIN, nSpheres=4), lambda: mssAssembly(LABELS, nSpheres=4)):
            with self.assertRaises(ValueError) as ctx:
                call()
            self.assertIn('give its voxel edge in metres, voxelSize=', str(ctx.exception))
        self.assertEqual(len(O.bodies), 0)
        cid, ids = mssClump(GRAIN, nSpheres=4, voxelSize=1.25e-5)
        self.assertLess(O.bodies[cid].state.mass, 1e-3)  # a sand grain: milligrams

    def test_eta_range(self):
        for eta in (-0.1, 1.0, 2.0, float('nan')):
            with self.assertRaises(ValueError) as ctx:
                mssClump(ELL, eta=eta, resolution=20)
            self.assertIn('eta must be in [0, 1)', str(ctx.exception))

    def test_rmin_above_the_inscribed_radius_says_so(self):
        with self.assertRaises(ValueError) as ctx:
            mssClump(ELL, rMin=1.5, resolution=30)
        msg = str(ctx.exception)
        self.assertIn('largest inscribed radius', msg)
        inscribed = float(msg.split('largest inscribed radius ')[1].split()[0])
        self.assertAlmostEqual(inscribed, 1.0, delta=0.05)  # the ellipsoid's semi-axes are 2, 1, 1
        self.assertEqual(len(O.bodies), 0)


class StrictArguments(Base):
    """Every public function's own arguments checked, YADE's errors named by the argument; nothing half-built."""

    def refused(self, kind, fragment, f):
        with self.assertRaises(kind) as ctx:
            f()
        self.assertIn(fragment, str(ctx.exception))
        self.assertEqual(len(O.bodies), 0)

    def test_clump_ids_by_name(self):
        # the attack: grainSizes(np.array([id])) and writeClumps(clumpIds=np.int64(id)) raised internal errors
        import tempfile
        from yade_mss import grainSizes, writeClumps
        cid, ids = mssClump(ELL, nSpheres=4, resolution=30)
        sizes, masses = grainSizes(np.array([cid]))
        self.assertEqual(len(sizes), 1)
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, 'c.txt')
            self.assertEqual(writeClumps(path, np.array([cid]))[0], 1)
            for kind, fragment, f in (
                    (TypeError, 'clumpIds must be a list', lambda: grainSizes(np.int64(cid))),
                    (TypeError, 'clumpIds must be a list', lambda: writeClumps(path, clumpIds=np.int64(cid))),
                    (TypeError, 'clump ids must be integers', lambda: grainSizes(['x'])),
                    (TypeError, 'clump ids must be integers', lambda: writeClumps(path, [True])),
                    (ValueError, 'is not a clump', lambda: grainSizes([ids[0]])),
                    (ValueError, 'is not a clump', lambda: writeClumps(path, [10 ** 6]))):
                with self.assertRaises(kind) as ctx:
                    f()
                self.assertIn(fragment, str(ctx.exception))

    def test_own_parameters_are_suggested(self):
        r = generate(ELL, nSpheres=4, resolution=30)
        self.refused(TypeError, "did you mean 'orientation'", lambda: mssClump(r, orientaton='random'))
        self.refused(TypeError, "did you mean 'seed'", lambda: mssClump(r, seeed=3))
        t = mssTemplate(r)
        self.refused(TypeError, "did you mean 'num'", lambda: mssClumpCloud([t], (0, 0, 0), (9, 9, 9), nmu=3))
        self.refused(TypeError, "did you mean 'psdSizes'",
                     lambda: mssClumpCloud([t], (0, 0, 0), (9, 9, 9), psdSize=[1, 2]))

    def test_types_and_ranges(self):
        r = generate(ELL, nSpheres=4, resolution=30)
        t = mssTemplate(r)
        self.refused(TypeError, 'mask must be an integer', lambda: mssClump(r, mask='a'))
        self.refused(ValueError, 'color must be 3 numbers, got 2', lambda: mssClump(r, color=(1, 0)))
        self.refused(TypeError, "center must be 3 numbers, got the string 'abc'", lambda: mssClump(r, center='abc'))
        self.refused(TypeError, 'scale must be a number', lambda: mssClump(r, scale='2'))
        self.refused(TypeError, 'nSpheres must be an integer, got True', lambda: mssClump(ELL, nSpheres=True))
        self.refused(ValueError, 'resolution must be an integer, got 30.5',
                     lambda: mssClump(ELL, nSpheres=3, resolution=30.5))
        for num in (-5, 0, 2.5, True):
            self.refused((ValueError, TypeError), 'num', lambda: mssClumpCloud([t], (0, 0, 0), (9, 9, 9), num=num))
        self.refused(TypeError, 'seed must be an integer', lambda: mssClump(r, orientation='random', seed='x'))
        self.refused(TypeError, 'periodic must be True or False',
                     lambda: mssClumpCloud([t], (0, 0, 0), (9, 9, 9), periodic=1))

    def test_yade_errors_name_the_argument(self):
        r = generate(ELL, nSpheres=4, resolution=30)
        self.refused(ValueError, "material='nonexistent'", lambda: mssClump(r, material='nonexistent'))
        self.refused(ValueError, 'material=17', lambda: mssClump(r, material=17))

    def test_tiff_where_npy_is_read(self):
        import tempfile
        import tifffile
        a = np.zeros((12, 12, 12), dtype=np.uint8)
        a[2:10, 3:9, 2:10] = 1
        with tempfile.TemporaryDirectory() as d:
            tifffile.imwrite(os.path.join(d, 'g.tif'), a)
            cid, ids = mssClump(os.path.join(d, 'g.tif'), nSpheres=3, voxelSize=1e-4)
        self.assertGreaterEqual(len(ids), 1)


class Packing(Base):
    def test_template_radii(self):
        t = mssTemplate(ELL, nSpheres=10, resolution=40, scale=2.0)
        # equivalent radius: of the grain's volume (the ellipsoid 2, 1, 1: (2)^(1/3)), scaled
        self.assertAlmostEqual(t.equivalentRadius, 2.0 * 2 ** (1 / 3.0), delta=0.01)
        # bounding radius: every sphere lies inside it, one touches it
        d = np.linalg.norm(t.spherePackCenters, axis=1) + t.spherePackRadii
        self.assertAlmostEqual(d.max(), t.boundingRadius, places=12)
        self.assertGreater(t.boundingRadius / t.equivalentRadius, 1.3)  # why replaceByClumps overlaps

    def test_random_orientation_is_seeded(self):
        r = generate(FEMUR, nSpheres=8, resolution=30)
        oris = []
        for seed in (1, 1, 2):
            cid, ids = mssClump(r, orientation='random', seed=seed)
            oris.append(np.array([vec(O.bodies[i].state.pos) for i in ids]))
        np.testing.assert_allclose(oris[0], oris[1], atol=1e-12)
        self.assertGreater(np.abs(oris[0] - oris[2]).max(), 1.0)
        with self.assertRaises(ValueError):
            mssClump(r, orientation='randm')

    def test_cloud_with_a_size_distribution(self):
        t1 = mssTemplate(ELL, nSpheres=6, resolution=30)
        t2 = mssTemplate(FEMUR, nSpheres=6, resolution=30)
        sizes, cumm = [0.002, 0.003, 0.004], [0.0, 0.5, 1.0]
        out = mssClumpCloud([t1, t2], (0, 0, 0), (0.05, 0.05, 0.05), num=40, seed=5, psdSizes=sizes, psdCumm=cumm,
                            material='grain')
        self.assertEqual(len(out), 40)
        d = []
        for cid, ids in out:
            V = O.bodies[cid].state.mass / 2000.0
            d.append(2 * (3 * V / (4 * math.pi)) ** (1 / 3.0))
            for i in ids:  # inside the box
                p, r = vec(O.bodies[i].state.pos), O.bodies[i].shape.radius
                self.assertTrue(np.all(p - r >= -1e-9) and np.all(p + r <= 0.05 + 1e-9))
        d = np.array(d)
        self.assertTrue(np.all(d >= 0.002 * (1 - 1e-6)) and np.all(d <= 0.004 * (1 + 1e-6)), d)
        self.assertLess(abs(np.median(d) - 0.003), 0.0006)  # half below 3 mm
        self.assertGreater(smallestGap(out), 0)  # no two clumps touch
        with self.assertRaises(ValueError):
            mssClumpCloud([t1], (0, 0, 0), (1, 1, 1), num=5, psdSizes=[1, 2], psdCumm=[0, 0.5])

    def test_replace_by_clumps_without_overlaps(self):
        t = mssTemplate(ELL, nSpheres=8, resolution=30)
        sp = pack.SpherePack()
        sp.makeCloud((0, 0, 0), (0.1, 0.1, 0.1), rMean=0.008, rRelFuzz=0.2, num=40, seed=2)
        sp.toSimulation(material='grain')
        n = len(O.bodies)
        out = mssReplaceByClumps([t], [1.0], seed=3)
        self.assertEqual(len(out), n)
        self.assertGreater(smallestGap(out), -1e-12)
        self.assertEqual(sorted(k for c, k in restoreClumpProperties()), ['grain'] * n)


class Assembly(Base):
    def test_labelled_volume_and_finished_batch_directory(self):
        import tempfile
        from yade_mss import batch, mssAssembly, regions, syntheticSpecimen
        L = syntheticSpecimen((80, 80, 80), 8, size=(5, 10), seed=4)
        h, origin = 1e-4, (0.01, 0.02, 0.0)
        clumps = mssAssembly(L, voxelSize=h, origin=origin, nSpheres=6, material='grain')
        rs = {r.label: r for r in regions(L)}
        self.assertEqual(sorted(clumps), sorted(rs))
        for lab, (cid, ids) in clumps.items():
            st = O.bodies[cid].state
            self.assertLess(abs(st.mass / (2000 * rs[lab].voxels * h ** 3) - 1), 1e-9)  # the grain's own mass
            c = np.array(origin) + h * np.argwhere(L == lab).mean(axis=0)
            np.testing.assert_allclose(vec(st.pos), c, atol=1e-9)  # at its true position
            self.assertEqual(len(ids), 6)
        n = len(O.bodies)
        with tempfile.TemporaryDirectory() as d:
            batch(L, d, workers=1, nSpheres=6, voxelSize=h, origin=origin, progress=False)
            again = mssAssembly(d, material='grain')
            self.assertEqual(sorted(again), sorted(clumps))
            for lab in clumps:  # the same clumps from the directory
                a, b = O.bodies[clumps[lab][0]].state, O.bodies[again[lab][0]].state
                self.assertEqual(a.mass, b.mass)
                np.testing.assert_allclose(vec(a.pos), vec(b.pos), atol=1e-12)
            with self.assertRaises(ValueError):
                mssAssembly(d, nSpheres=3)  # nothing is generated for a finished batch
        self.assertEqual(len(O.bodies), 2 * n)  # as many again from the directory, none by the refusal
        with self.assertRaises(TypeError):
            mssAssembly(L, voxelSize=h, nSphere=3)

    def test_the_scans_contacts_interact_in_yade_and_the_time_step(self):
        import tempfile
        from yade_mss import batch, findContacts, mssAssembly, voronoiBall
        L = voronoiBall(24, 7, seed=3)
        h = 1e-3
        pairs = len(findContacts(L))
        O.engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb()]),
                     InteractionLoop([Ig2_Sphere_Sphere_ScGeom()], [Ip2_FrictMat_FrictMat_FrictPhys()],
                                     [Law2_ScGeom_FrictPhys_CundallStrack()]), NewtonIntegrator(gravity=(0, 0, 0))]
        a = mssAssembly(L, voxelSize=h, nSpheres=10, material='grain')
        self.assertEqual(len(a.scanContacts), pairs)
        step, setBy = a.timeStep()
        self.assertAlmostEqual(step, PWaveTimeStep(), delta=1e-12 * step)  # as YADE computes it
        self.assertTrue(setBy)
        O.dt = 0.1 * step
        O.step()
        kept, of = a.contactsKept()
        self.assertEqual(of, pairs)
        self.assertEqual(kept, pairs)  # every contact of the scan is an interaction in YADE
        # from a finished batch directory: the same contacts, read from its contacts.csv
        O.reset()
        O.materials.append(FrictMat(density=2000, young=1e7, label='grain'))
        O.engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb()]),
                     InteractionLoop([Ig2_Sphere_Sphere_ScGeom()], [Ip2_FrictMat_FrictMat_FrictPhys()],
                                     [Law2_ScGeom_FrictPhys_CundallStrack()]), NewtonIntegrator(gravity=(0, 0, 0))]
        with tempfile.TemporaryDirectory() as d:
            batch(L, d, workers=1, nSpheres=10, voxelSize=h, progress=False)
            b = mssAssembly(d, material='grain')
            self.assertEqual(sorted(b.scanContacts), sorted(a.scanContacts))
            O.dt = 0.1 * step
            O.step()
            self.assertEqual(b.contactsKept(), (pairs, pairs))

    def test_contacts_across_watershed_lines_interact_in_yade(self):
        # a packing segmented with watershed lines: no two grains share a face, every pair within one voxel
        # is a scan contact, counted again in YADE with the same tolerance, and an interaction after a step
        from yade_mss import findContacts, mssAssembly, packedSpecimen
        L = packedSpecimen((36, 36, 36), grains=20, size=(4, 6), seed=2)
        h = 1e-3
        self.assertEqual(findContacts(L, gap=0), [])
        pairs = {(c['a'], c['b']) for c in findContacts(L, gap=1)}
        self.assertGreater(len(pairs), 10)
        O.engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb()]),
                     InteractionLoop([Ig2_Sphere_Sphere_ScGeom()], [Ip2_FrictMat_FrictMat_FrictPhys()],
                                     [Law2_ScGeom_FrictPhys_CundallStrack()]), NewtonIntegrator(gravity=(0, 0, 0))]
        a = mssAssembly(L, voxelSize=h, nSpheres=6, minVoxels=10, material='grain')
        self.assertAlmostEqual(a.contactGap, h)
        built = {p for p in pairs if p[0] in a and p[1] in a}
        self.assertTrue(built <= a.pairsWithin())  # the scan's pairs are within the tolerance in YADE too
        self.assertTrue(built <= a.pairsWithin(0.0))  # and overlap
        O.dt = 0.1 * a.timeStep()[0]
        O.step()
        self.assertEqual(a.contactsKept(), (len(built), len(built)))

    def test_porosity_from_the_grains_exact_volumes(self):
        from yade_mss import generate, mssClump, porosity
        O.periodic = True
        O.cell.setBox(0.04, 0.04, 0.04)
        r = generate('tests/data/ellipsoid_2_1_1.stl', nSpheres=10)
        exact = 0.0
        for n in range(8):
            mssClump(r, scale=2e-3, center=(0.005 + 0.01 * (n % 4), 0.01 + 0.02 * (n // 4), 0.02),
                     material='grain')
            exact += r.targetMass.volume * 2e-3 ** 3
        self.assertAlmostEqual(porosity(), 1 - exact / 0.04 ** 3, delta=1e-12)
        self.assertAlmostEqual(porosity(volume=1e-4), 1 - exact / 1e-4, delta=1e-12)
        # YADE's sums every member: overlaps counted twice, the solid overestimated
        self.assertLess(utils.porosity(0.04 ** 3), porosity() - 1e-4)
        with self.assertRaises(ValueError):
            porosity(volume=-1.0)

    def test_porosity_of_a_scan_s_specimen_is_counted_in_the_scan_s_box(self):
        # the issue: the default box was the spheres' (1.5 voxels beyond the scan), so a CT specimen's porosity
        # differed from the scan's without a word
        from yade_mss import mssAssembly, porosity
        import tempfile
        L = np.load('tests/data/two_grains_labels.npy')
        h = 1e-3
        scan = 1 - np.count_nonzero(L) / L.size  # the scan's own porosity, voxels counted
        a = mssAssembly(L, nSpheres=20, voxelSize=h, material='grain')
        solid = sum(O.bodies[cid].state.mass for cid, _ in a.values()) / O.materials['grain'].density
        self.assertAlmostEqual(porosity(), 1 - solid / (L.size * h ** 3), delta=1e-12)  # the scan's box
        self.assertAlmostEqual(porosity(), scan, delta=0.01)  # the grains' exact volumes are their voxels'
        with tempfile.TemporaryDirectory() as d:  # a finished batch's folder: its manifest keeps the box
            from yade_mss import batch
            batch(L, os.path.join(d, 'b'), workers=1, progress=False, nSpheres=20, voxelSize=h)
            O.reset()
            O.materials.append(FrictMat(density=2650, label='grain'))
            mssAssembly(os.path.join(d, 'b'), material='grain')
            self.assertAlmostEqual(porosity(), 1 - solid / (L.size * h ** 3), delta=1e-9)


if __name__ == '__main__':
    result = unittest.main(exit=False, verbosity=2).result
    print('%d passed, %d failed' % (result.testsRun - len(result.failures) - len(result.errors),
                                   len(result.failures) + len(result.errors)))
    sys.exit(0 if result.wasSuccessful() else 1)
