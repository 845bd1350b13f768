"""A batch's report leads to the problems: each grain's reasons, worst first, the border and the time step in view,
the radius bound applied to every grain; the same grain gives the same clump alone and inside a batch; the
assembly's .vtk read by VTK itself; the page read by headless Chromium. Run with /usr/bin/python3."""
import csv
import os
import subprocess
import tempfile
import unittest

import numpy as np

from yade_mss import batch, generate, syntheticSpecimen
from yade_mss.specimens._report import THIN_VOXELS, _gap
from yade_mss import findContacts, voronoiBall

BINARY = os.environ.get('MSS_BINARY', 'mss')


def ball(shape, centre, radius):
    g = np.indices(shape).transpose(1, 2, 3, 0) - np.asarray(centre, dtype=float)
    return (g ** 2).sum(axis=-1) <= radius ** 2


def handMade():
    """1: a ball well inside; 2: a plate three voxels thick (thin); 3: a ball cut by the border; 4: a small
    ball (radius 2 voxels)."""
    L = np.zeros((60, 48, 40), dtype=np.int32)
    L[ball(L.shape, (14, 14, 20), 9)] = 1
    L[36:56, 6:40, 18:21] = 2
    L[ball(L.shape, (14, 40, 36), 8)] = 3
    L[ball(L.shape, (40, 40, 8), 2)] = 4
    return L


def tableRows(path):
    """The report's table as the browser built it: the cells of each row (headless Chromium's DOM)."""
    import html.parser

    class Cells(html.parser.HTMLParser):
        def __init__(self):
            super().__init__()
            self.rows, self.inCell = [], False

        def handle_starttag(self, tag, attrs):
            if tag == 'tr':
                self.rows.append([])
            elif tag in ('td', 'th'):
                self.inCell = True
                self.rows[-1].append('')

        def handle_endtag(self, tag):
            if tag in ('td', 'th'):
                self.inCell = False

        def handle_data(self, data):
            if self.inCell:
                self.rows[-1][-1] += data
    with tempfile.TemporaryDirectory() as profile:
        dom = subprocess.run(['chromium', '--headless', '--no-sandbox', '--disable-gpu', '--no-first-run',
                              '--disable-background-networking', '--user-data-dir=' + profile,
                              '--virtual-time-budget=3000', '--dump-dom', 'file://' + os.path.abspath(path)],
                             capture_output=True, text=True, timeout=120).stdout
    p = Cells()
    p.feed(dom)
    return p.rows


class Report(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.TemporaryDirectory()
        cls.L = handMade()
        cls.out = os.path.join(cls.dir.name, 'out')
        cls.b = batch(cls.L, cls.out, workers=1, nSpheres=12, progress=False, previews=True, density=2650,
                      young=7e10)

    @classmethod
    def tearDownClass(cls):
        cls.dir.cleanup()

    def test_the_worst_grain_first_with_its_reasons(self):
        b = self.b
        self.assertEqual(b.ranked[0], 'label_2')  # the plate
        self.assertIn('thin', b.rows['label_2']['problems'])
        self.assertLess(float(b.rows['label_2']['thickness_voxels']), THIN_VOXELS)
        self.assertIn('cut by the border', b.rows['label_3']['problems'])
        self.assertNotIn('cut by the border', b.rows['label_1']['problems'])
        self.assertEqual(b.rows['label_1']['problems'], '')  # nothing to say of a plain ball
        # the page, as Chromium built it: the plate in the first row, the border and the time step said
        cells = tableRows(os.path.join(self.out, 'report.html'))
        header = next(r for r in cells if r and r[0] == '#')
        first = cells[cells.index(header) + 1]
        self.assertEqual(first[header.index('label')], '2')
        self.assertIn('thin', first[header.index('problems')])
        with open(os.path.join(self.out, 'report.html')) as f:
            page = f.read()
        self.assertIn('1 of 4 grains are cut by the volume', page)
        self.assertIn('set by label_', page)

    def test_the_pictures_drawn_alongside_are_those_drawn_in_one_process(self):
        """A batch draws the report's pictures in a forked child while it counts the contacts and writes the
        rest: the outputs are byte for byte those of a batch that does it all in one process (the run's times
        aside: grains.csv and report.html say them)."""
        from yade_mss.base import _alongside
        from yade_mss.specimens import _report
        with tempfile.TemporaryDirectory() as d:
            pids, draw = os.path.join(d, 'pids'), _report.drawPictures

            def recorded(*a):  # where the pictures were drawn
                with open(pids, 'a') as f:
                    f.write('%d\n' % os.getpid())
                return draw(*a)
            written = {}
            for how in ('alongside', 'one process'):
                out = os.path.join(d, how.replace(' ', '_'))
                can = _alongside.canFork
                _report.drawPictures = recorded
                if how == 'one process':
                    _alongside.canFork = lambda: False
                try:
                    batch(self.L, out, workers=1, nSpheres=12, progress=False, density=2650, young=7e10)
                finally:
                    _alongside.canFork, _report.drawPictures = can, draw
                written[how] = {}
                for name in sorted(os.listdir(out)):
                    if name not in ('grains', 'grains.csv', 'report.html', 'batch.json', '.mss.lock'):
                        with open(os.path.join(out, name), 'rb') as f:
                            written[how][name] = f.read()
            with open(pids) as f:
                child, here = [int(x) for x in f.read().split()]
            self.assertNotEqual(child, os.getpid())
            self.assertEqual(here, os.getpid())
        self.assertEqual(sorted(written['alongside']), ['assembly.txt', 'assembly.vtk', 'contacts.csv',
                                                        'report_distributions.png'])
        for name, data in written['alongside'].items():
            self.assertEqual(data, written['one process'][name], name)

    def test_the_time_step_and_who_sets_it(self):
        b = self.b
        steps = {k: float(r.radii.min()) * np.sqrt(2650 / 7e10) for k, r in b.results.items()}
        self.assertAlmostEqual(b.timeStep, min(steps.values()), delta=1e-15)
        self.assertEqual(b.setBy[0], min(steps, key=steps.get))
        self.assertTrue(all(steps[k] <= 1.1 * b.timeStep for k in b.setBy))
        for k, r in b.results.items():
            row = b.rows[k]
            self.assertAlmostEqual(row['time_step'], steps[k], delta=1e-15)
            self.assertAlmostEqual(row['r_min'], r.radii.min(), delta=1e-12)
            self.assertEqual(r.timeStep(2650, 7e10), steps[k])
        with open(os.path.join(self.out, 'grains.csv')) as f:
            written = {r['label']: r for r in csv.DictReader(f)}
        self.assertAlmostEqual(float(written['1']['time_step']), steps['label_1'], delta=1e-15)
        self.assertIn('sets the time step', b.rows[b.setBy[0]]['problems'])

    def test_previews_only_of_the_grains_worth_a_look(self):
        pngs = sorted(f[:-4] for f in os.listdir(os.path.join(self.out, 'grains')) if f.endswith('.png'))
        self.assertEqual(pngs, sorted(self.b.previewed))
        self.assertIn('label_2', self.b.previewed)
        self.assertNotIn('label_1', self.b.previewed)

    def test_the_assembly_vtk_as_vtk_reads_it(self):
        import vtk
        r = vtk.vtkPolyDataReader()
        r.SetFileName(os.path.join(self.out, 'assembly.vtk'))
        r.Update()
        poly = r.GetOutput()
        spheres = sum(len(x) for x in self.b.results.values())
        self.assertEqual(poly.GetNumberOfPoints(), spheres)
        self.assertEqual(poly.GetNumberOfVerts(), spheres)
        data = poly.GetPointData()
        radius = np.array([data.GetArray('radius').GetValue(i) for i in range(spheres)])
        ids = np.array([data.GetArray('clump_id').GetValue(i) for i in range(spheres)])
        dice = np.array([data.GetArray('dice').GetValue(i) for i in range(spheres)])
        points = np.array([poly.GetPoint(i) for i in range(spheres)])
        at = 0
        for k, res in self.b.results.items():
            n = len(res)
            np.testing.assert_array_equal(radius[at:at + n], res.radii)
            np.testing.assert_array_equal(points[at:at + n], res.centers)
            self.assertTrue(np.all(ids[at:at + n] == self.b.rows[k]['label']))
            self.assertTrue(np.all(dice[at:at + n] == self.b.rows[k]['dice']))
            at += n

    def test_a_rerun_says_what_it_did(self):
        again = batch(self.L, self.out, workers=1, nSpheres=12, progress=False, density=2650, young=7e10)
        self.assertEqual(again.generated, 0)
        with open(os.path.join(self.out, 'report.html')) as f:
            page = f.read()
        # previews off: another batch, its grains reused, its page written anew
        self.assertFalse(again.upToDate)
        self.assertIn('0 grains generated, 4 grains reused from an earlier run with the same input', page)
        self.assertEqual(again.ranked, self.b.ranked)
        # the same again: up to date, nothing written
        before = os.stat(os.path.join(self.out, 'report.html')).st_mtime_ns
        third = batch(self.L, self.out, workers=1, nSpheres=12, progress=False, density=2650, young=7e10)
        self.assertTrue(third.upToDate)
        self.assertEqual(third.ranked, self.b.ranked)
        self.assertEqual(os.stat(os.path.join(self.out, 'report.html')).st_mtime_ns, before)


class RadiusBound(unittest.TestCase):
    def test_rmin_voxels_holds_for_every_grain_and_too_small_ones_are_reported(self):
        L = handMade()
        b = batch(L, None, workers=1, nSpheres=12, rMinVoxels=2.5, voxelSize=0.01, progress=False)
        self.assertEqual(b.rows['label_4']['status'], 'skipped')  # radius 2 voxels: cannot hold 2.5
        self.assertIn('too small for the radius bound', b.rows['label_4']['problems'])
        self.assertEqual(b.rows['label_2']['status'], 'skipped')  # the plate, 3 voxels thick
        for k, r in b.results.items():
            self.assertGreaterEqual(r.radii.min(), 2.5 * 0.01 * (1 - 1e-12), k)  # none shrunk under it
            self.assertGreaterEqual(b.rows[k]['r_min_voxels'], 2.5 * (1 - 1e-12))
        self.assertEqual(sorted(b.results), ['label_1', 'label_3'])
        # world units and voxels: the larger bound applies
        r = generate(L == 1, nSpheres=12, rMin=3.0, rMinVoxels=2.0)
        self.assertGreaterEqual(r.radii.min(), 3.0)
        self.assertEqual(r.metrics['smallestRadius'], r.radii.min())


class Contacts(unittest.TestCase):
    """The bar: a ball of 50 voxels radius cut into 12 Voronoi cells, every grain touching its neighbours."""

    @classmethod
    def setUpClass(cls):
        cls.L = voronoiBall(50, 12, seed=1)
        cls.on = batch(cls.L, None, workers=2, dice=0.03, nSpheres=40, progress=False)
        cls.off = batch(cls.L, None, workers=2, dice=0.03, nSpheres=40, progress=False, contacts=False)

    def gaps(self, b):
        by = {b.rows[k]['label']: b.results[k] for k in b.results}
        return [_gap(by[c['a']], by[c['b']]) for c in findContacts(self.L)]

    def test_every_contact_of_the_scan_kept(self):
        c = self.on.contacts
        self.assertEqual(c['pairs'], len(findContacts(self.L)))
        self.assertGreaterEqual(c['pairs'], 20)
        self.assertEqual(c['kept'], c['pairs'])  # 100%
        self.assertTrue(all(g <= 0.5 for g in self.gaps(self.on)))
        self.assertEqual(c['coordinationAssembly'], c['coordinationScan'])
        self.assertFalse(all(g <= 0.5 for g in self.gaps(self.off)))  # without: some are lost
        self.assertIsNone(self.off.contacts)
        for k, row in self.on.rows.items():
            self.assertEqual(row['contacts_kept'], row['contacts_ct'], k)
            self.assertGreater(row['contacts_ct'], 0)

    def test_no_bump_and_the_same_fidelity(self):
        added = 0
        for k, r in self.on.results.items():
            m = r.metrics
            self.assertLessEqual(m['protrusion'], m['protrusionLimit'] + 1e-12, k)  # nothing beyond the bound
            self.assertEqual(m['contactsMissed'], 0, k)
            added += m['contactsAdded']
            self.assertLessEqual(self.on.rows[k]['dice'], 1.10 * self.off.rows[k]['dice'], k)
        self.assertGreater(added, 0)

    def test_the_radius_bound_holds_for_contact_balls_and_what_it_costs_is_reported(self):
        b = batch(self.L, None, workers=2, dice=0.03, nSpheres=40, progress=False, rMinVoxels=3.0)
        for k, r in b.results.items():
            self.assertGreaterEqual(r.radii.min(), 3.0 * (1 - 1e-12), k)  # no contact ball under the bound
        lost = [k for k, row in b.rows.items() if row['contacts_kept'] < row['contacts_ct']]
        self.assertEqual(b.contacts['kept'] < b.contacts['pairs'], bool(lost))
        for k in lost:
            self.assertIn('contacts in the scan lost', b.rows[k]['problems'])
        # without the bound every contact is held, by smaller balls where only those fit
        self.assertLessEqual(min(r.radii.min() for r in self.on.results.values()),
                             min(r.radii.min() for r in b.results.values()))

    def test_half_the_bound_into_neighbours_keeps_overlaps_under_it(self):
        half = batch(self.L, None, workers=2, dice=0.03, nSpheres=40, progress=False, neighbourProtrusion=0.5)
        self.assertEqual(half.contacts['kept'], half.contacts['pairs'])
        self.assertLessEqual(half.contacts['overlap'], 1.0 + 1e-9)  # the bound: one voxel
        self.assertGreater(self.on.contacts['overlap'], 1.0)  # the full bound each side: more

    def test_alone_and_in_the_batch_byte_for_byte(self):
        with tempfile.TemporaryDirectory() as d:
            vol = os.path.join(d, 'v.npy')
            np.save(vol, self.L)
            for share in ('1', '0.5'):
                out = os.path.join(d, 'out' + share)
                batch([vol], out, workers=2, dice=0.03, nSpheres=40, progress=False, neighbourProtrusion=float(share))
                for label in (1, 5, 9):
                    alone = os.path.join(d, 'alone.csv')
                    subprocess.run([BINARY, 'generate', vol, '--label', str(label), '--dice', '0.03', '--spheres',
                                    '40', '--neighbour-protrusion', share, '-o', alone], check=True,
                                   capture_output=True)
                    with open(alone, 'rb') as f, open(os.path.join(out, 'grains', 'label_%d.csv' % label), 'rb') as g:
                        self.assertEqual(f.read(), g.read(), (share, label))
            # the command line reads every label of any integer type and order: the same contacts, the same bytes
            other = os.path.join(d, 'f.npy')
            np.save(other, np.asfortranarray(self.L.astype(np.uint16)))
            alone = os.path.join(d, 'alone.csv')
            subprocess.run([BINARY, 'generate', other, '--label', '9', '--dice', '0.03', '--spheres', '40', '-o',
                            alone], check=True, capture_output=True)
            with open(alone, 'rb') as f, open(os.path.join(d, 'out1', 'grains', 'label_9.csv'), 'rb') as g:
                self.assertEqual(f.read(), g.read())
            r = generate(vol, label=5, dice=0.03, nSpheres=40)  # Python alone, from the file
            np.testing.assert_array_equal(r.centers, self.on.results['label_5'].centers)
            np.testing.assert_array_equal(r.radii, self.on.results['label_5'].radii)


class ContactsInSlabs(unittest.TestCase):
    def test_slabs_give_the_whole_volumes_contacts(self):
        import yade_mss.grains._volumes as spec
        L = voronoiBall(30, 9, seed=2)
        whole = findContacts(L, 0.5, (1.0, 2.0, 3.0))
        saved = spec.SLAB_VOXELS
        try:
            for voxels in (1, 61 * 61 * 2, 7 * 61 * 61):  # one layer a slab, two, seven
                spec.SLAB_VOXELS = voxels
                self.assertEqual(findContacts(L, 0.5, (1.0, 2.0, 3.0)), whole, voxels)
        finally:
            spec.SLAB_VOXELS = saved

    def test_a_memory_mapped_volume_is_read_a_slab_at_a_time(self):
        import tracemalloc
        import yade_mss.grains._volumes as spec
        L = voronoiBall(60, 20, seed=4)  # 125^3 voxels: 7.8 MB of int32, 15.6 MB as int64
        with tempfile.TemporaryDirectory() as d:
            np.save(os.path.join(d, 'v.npy'), L)
            mapped = np.load(os.path.join(d, 'v.npy'), mmap_mode='r')
            saved = spec.SLAB_VOXELS
            spec.SLAB_VOXELS = 1 << 16  # slabs of 0.5 MB as int64
            try:
                tracemalloc.start()
                got = findContacts(mapped)
                peak = tracemalloc.get_traced_memory()[1]
                tracemalloc.stop()
            finally:
                spec.SLAB_VOXELS = saved
            del mapped
        self.assertEqual(got, findContacts(L))
        self.assertLess(peak, 3 << 20)  # a few slabs, not the volume's 15.6 MB


class BatchMemory(unittest.TestCase):
    def test_a_batch_holds_the_grains_in_flight_not_the_volume(self):
        import tracemalloc
        import yade_mss.grains._volumes as spec
        from yade_mss.specimens import makeTasks
        L = voronoiBall(80, 60, seed=5)  # 165^3 int32: 17 MB
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, 'v.npy')
            np.save(path, L)
            saved = spec.SLAB_VOXELS
            spec.SLAB_VOXELS = 1 << 16
            try:
                tracemalloc.start()
                tasks, skipped, key, found = makeTasks([path], {'nSpheres': 8})  # memory-mapped, in slabs
                peak = tracemalloc.get_traced_memory()[1]
                tracemalloc.stop()
                self.assertEqual(len(tasks), 60)
                self.assertLess(peak, L.nbytes / 4)  # the tasks cut their crops when they run
                np.testing.assert_array_equal(tasks[7].crop, np.pad(L[regionsBox(L, tasks[7].label)] ==
                                                                    tasks[7].label, 2))
                b = batch([path], None, workers=2, nSpheres=8, progress=False)
            finally:
                spec.SLAB_VOXELS = saved
            self.assertEqual(len(b.results), 60)
            self.assertEqual(b.contacts['kept'], b.contacts['pairs'])


def regionsBox(L, label):
    idx = np.argwhere(L == label)
    return tuple(slice(a, b + 1) for a, b in zip(idx.min(0), idx.max(0)))


class SameGrainSameClump(unittest.TestCase):
    def test_a_label_alone_and_inside_a_batch_byte_for_byte(self):
        L = syntheticSpecimen((70, 70, 70), grains=10, seed=4)
        with tempfile.TemporaryDirectory() as d:
            vol = os.path.join(d, 'v.npy')
            np.save(vol, L)
            out = os.path.join(d, 'out')
            b = batch([vol], out, workers=2, dice=0.03, nSpheres=40, progress=False)
            self.assertGreaterEqual(len(b.results), 8)
            for k in b.results:
                label = b.rows[k]['label']
                alone = os.path.join(d, 'alone_%d.csv' % label)
                subprocess.run([BINARY, 'generate', vol, '--label', str(label), '--dice', '0.03', '--spheres', '40',
                                '-o', alone], check=True, capture_output=True)
                with open(alone, 'rb') as f, open(os.path.join(out, 'grains', k + '.csv'), 'rb') as g:
                    self.assertEqual(f.read(), g.read(), k)

    def test_wherever_the_grain_sits_in_the_array(self):
        L = syntheticSpecimen((70, 70, 70), grains=6, seed=8)
        for label in range(1, int(L.max()) + 1):
            solid = L == label
            idx = np.argwhere(solid)
            lo, hi = idx.min(0), idx.max(0) + 1
            crop = solid[lo[0]:hi[0], lo[1]:hi[1], lo[2]:hi[2]]
            ref = generate(solid, nSpheres=25)
            for pad in ((1, 1, 1), (3, 0, 2), (9, 5, 4)):
                big = np.zeros(np.array(crop.shape) + np.array(pad) + 4, dtype=bool)
                big[pad[0]:pad[0] + crop.shape[0], pad[1]:pad[1] + crop.shape[1], pad[2]:pad[2] + crop.shape[2]] = crop
                moved = generate(big, nSpheres=25, origin=tuple(float(x) for x in lo - np.array(pad)))
                self.assertEqual(len(moved), len(ref))
                np.testing.assert_allclose(moved.centers, ref.centers, rtol=0, atol=1e-9)
                np.testing.assert_allclose(moved.radii, ref.radii, rtol=0, atol=1e-9)


if __name__ == '__main__':
    unittest.main()
