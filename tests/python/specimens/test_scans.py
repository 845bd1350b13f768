"""Real segmentations in: contacts across watershed lines (a packing segmented as real pipelines do, a touching
Voronoi specimen with lines), binary scans refused or segmented, a rerun of a finished batch that does nothing,
honest counts where a specimen shows no contacts, reruns that check every file they reuse, one batch a folder,
outputs refused before any work. Small sizes; bench/batch_scale.py runs the large ones. Run with
/usr/bin/python3."""
import csv
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
import unittest

import numpy as np

from yade_mss import batch, findContacts, generate, packedSpecimen, regions, voronoiBall
from yade_mss.specimens import _manifest
from yade_mss.specimens._report import gapsText
from yade_mss.grains import segmentBinary, segmentScan, separated
from yade_mss.specimens import bestOverlap, porousScan

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..', 'data')


def bruteGaps(L):
    """{(a, b): the least gap between the voxel cubes of labels a < b}, by every pair of their voxels (the
    oracle: no stencil, no boundary)."""
    labels = [int(x) for x in np.unique(L) if x != 0]
    where = {a: np.argwhere(L == a) for a in labels}
    out = {}
    for n, a in enumerate(labels):
        for b in labels[n + 1:]:
            pa, pb = where[a], where[b]
            if (np.maximum(pa.min(0), pb.min(0)) - np.minimum(pa.max(0), pb.max(0)) > 3).any():
                continue  # boxes more than 3 voxels apart on some axis
            d = np.abs(pa[:, None, :] - pb[None, :, :])
            g = np.sqrt((np.maximum(d - 1, 0) ** 2).sum(axis=-1)).min()
            out[(a, b)] = float(g)
    return out


class WatershedLines(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.L = packedSpecimen((48, 48, 48), grains=40, size=(4, 7), seed=5)
        cls.gaps = bruteGaps(cls.L)

    def test_lines_hide_every_shared_face(self):
        self.assertGreater(int(self.L.max()), 20)
        self.assertEqual(findContacts(self.L, gap=0), [])  # the usual count sees nothing

    def test_pairs_within_the_tolerance_are_exactly_the_oracles(self):
        for tol in (1.0, 1.5, 2.0):
            want = {k: g for k, g in self.gaps.items() if g <= tol + 1e-9}
            got = {(c['a'], c['b']): c['gap'] for c in findContacts(self.L, gap=tol)}
            self.assertEqual(set(got), set(want), tol)
            for k in want:
                self.assertAlmostEqual(got[k], want[k], places=12)
        self.assertGreater(sum(1 for g in self.gaps.values() if g <= 1.0), 30)

    def test_every_scan_contact_is_kept_within_half_a_voxel(self):
        b = batch(self.L, None, workers=1, progress=False, nSpheres=6)
        c = b.contacts
        self.assertEqual(c['gap'], 1.0)
        self.assertEqual(c['pairs'], sum(1 for g in self.gaps.values() if g <= 1.0))
        self.assertEqual(len(b.results), int(self.L.max()))  # every grain, the watershed's smallest fragments too
        self.assertGreater(c['between'], 30)
        self.assertEqual(c['between'], c['pairs'])
        self.assertEqual(c['kept'], c['pairs'])  # every pair of the scan within half a voxel in the assembly
        # no bump: every grain within its bound but for the contact balls' reach (half a voxel and a twentieth)
        for k, r in b.results.items():
            self.assertLessEqual(r.metrics['protrusion'], 1.0 + 1e-9, k)
        # counted with the same tolerance in the assembly: the kept pairs at least
        self.assertGreaterEqual(c['assembly'], c['kept'])

    def test_a_label_alone_is_the_same_as_in_the_batch(self):
        b = batch(self.L, None, workers=1, progress=False, nSpheres=6, labels=[3, 7])
        for label in (3, 7):
            alone = generate(self.L, label=label, nSpheres=6)
            inBatch = b.results['label_%d' % label]
            np.testing.assert_array_equal(alone.centers, inBatch.centers)
            np.testing.assert_array_equal(alone.radii, inBatch.radii)

    def test_a_gap_of_zero_is_the_count_of_shared_faces(self):
        b = batch(self.L, None, workers=1, progress=False, nSpheres=4, minVoxels=20, contactGap=0)
        self.assertEqual(b.contacts['pairs'], 0)
        self.assertIn('No two grains of the scan come within 0 voxels', gapsText(b.contacts))
        self.assertIsNotNone(b.contacts['nearby'])
        self.assertGreater(len(b.contacts['nearby']), 30)  # the gaps of the neighbours, to say why
        self.assertAlmostEqual(min(b.contacts['nearby']), min(self.gaps.values()))


class VoronoiWithLines(unittest.TestCase):
    def test_every_contact_of_a_touching_specimen_with_lines_is_kept(self):
        touching = voronoiBall(radius=16, cells=10, seed=2)
        L = voronoiBall(radius=16, cells=10, seed=2, lines=True)
        self.assertEqual(findContacts(L, gap=0), [])
        faces = {(c['a'], c['b']) for c in findContacts(touching, gap=0)}
        lines = {(c['a'], c['b']) for c in findContacts(L, gap=1)}
        self.assertTrue(faces <= lines)  # every face shared before the lines is a contact across them
        b = batch(L, None, workers=1, progress=False, nSpheres=8)
        self.assertEqual(b.contacts['kept'], b.contacts['pairs'])
        self.assertGreaterEqual(b.contacts['pairs'], len(faces))
        for k, r in b.results.items():
            self.assertEqual(r.metrics['contactsMissed'], 0, k)

    def test_bad_specimen_arguments_name_themselves(self):
        with self.assertRaisesRegex(TypeError, 'size must be'):
            packedSpecimen((20, 20, 20), 3, size=(2, 3, 4))
        with self.assertRaisesRegex(ValueError, 'gap'):
            findContacts(np.zeros((4, 4, 4), dtype=np.int32), gap=9)
        with self.assertRaisesRegex(ValueError, 'segmentH'):
            segmentBinary(np.ones((4, 4, 4), dtype=bool), h=-1)

    def test_separated_clears_one_side_of_each_shared_face(self):
        L = np.zeros((6, 3, 3), dtype=np.int32)
        L[:3], L[3:] = 1, 2
        S = separated(L)
        self.assertTrue((S[2] == 0).all() and (S[:2] == 1).all() and (S[3:] == 2).all())


class BinaryScans(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.L = packedSpecimen((40, 40, 40), grains=25, size=(4, 6), seed=9)
        cls.binary = (cls.L != 0).astype(np.uint8) * 255  # a thresholded scan: 0 and 255

    def test_a_binary_scan_is_refused_naming_the_fix(self):
        for scan in (self.binary, self.binary != 0):
            with self.assertRaises(ValueError) as e:
                batch(scan, None, workers=1, progress=False, nSpheres=4)
            text = str(e.exception)
            self.assertIn('binary scan', text)
            self.assertIn('--segment', text)
            self.assertIn('separate pieces', text)

    def test_one_grain_of_one_value_is_still_a_grain(self):
        one = np.zeros((20, 20, 20), dtype=np.uint8)
        one[5:15, 5:15, 5:12] = 1
        b = batch(one, None, workers=1, progress=False, nSpheres=4)
        self.assertEqual(len(b.results), 1)

    def test_segment_cuts_it_into_grains_and_writes_the_labels(self):
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, 'scan.npy')
            np.save(path, self.binary)
            out = os.path.join(d, 'out')
            b = batch([path], out, workers=1, progress=False, nSpheres=4, segment=True, minVoxels=10)
            labels = np.load(os.path.join(out, 'labels.npy'))
            self.assertEqual(labels.shape, self.binary.shape)
            info = b.segmented['info']
            self.assertTrue(((labels != 0) <= (self.binary != 0)).all())  # grains only where the scan is solid
            self.assertEqual(int(np.count_nonzero((labels == 0) & (self.binary != 0))),
                             info['speckVoxels'] + info['smallVoxels'])  # the rest: dropped, and said so
            self.assertGreaterEqual(int(np.bincount(labels.ravel())[1:].min()), 10)  # none under --min-voxels
            self.assertGreater(int(labels.max()), 10)
            self.assertGreater(len(b.results), 10)
            with open(os.path.join(out, 'report.html')) as f:
                page = f.read()
            self.assertIn('segmented here into', page)
            self.assertTrue(os.path.getsize(os.path.join(out, 'report_segmentation.png')) > 1000)
            with self.assertRaises(ValueError) as e:  # labels are not a binary scan
                batch(self.L, None, workers=1, progress=False, nSpheres=4, segment=True)
            self.assertIn('holds labels', str(e.exception))
            with self.assertRaises(ValueError):  # segmentH alone means nothing
                batch(self.L, None, workers=1, progress=False, nSpheres=4, segmentH=2.0)
            self.assertIn('Dropped: ', page)
            self.assertIn('typical inscribed radius R', page)

    def test_segmentation_separates_two_touching_balls(self):
        g = np.indices((40, 24, 24)).transpose(1, 2, 3, 0)
        solid = (((g - (12, 12, 12)) ** 2).sum(-1) <= 81) | (((g - (27, 12, 12)) ** 2).sum(-1) <= 81)
        for h in (None, 1.0):  # the default, and a height given
            labels = segmentBinary(solid, h)
            self.assertEqual(int(labels.max()), 2)
            self.assertNotEqual(labels[12, 12, 12], labels[27, 12, 12])

    def test_porous_scans_are_segmented_well_at_the_defaults(self):
        # thresholded scans of touching porous grains (10 % intra-grain pores, some open; 300 specks; noise): the
        # fixed h = 1 shattered such grains (a real scan: 6,479 segments for 34 grains, median Jaccard 0.36)
        for seed in (1, 2, 3):
            scan, truth = porousScan((120, 120, 120), grains=40, size=(12, 20), porosity=0.1, seed=seed)
            labels, info = segmentScan(scan, minVoxels=100)
            j = bestOverlap(labels, truth)
            self.assertGreaterEqual(float(np.median(j)), 0.8, (seed, info['method']))
            self.assertLess(abs(info['grains'] - int(truth.max())), 0.25 * int(truth.max()), info)
            self.assertGreaterEqual(int(np.bincount(labels.ravel())[1:].min()), 100)  # no speck a grain
            self.assertGreater(info['specks'], 50)  # the scan's specks, dropped and counted

    def test_a_scan_of_specks_only_says_so(self):
        # every piece dropped: the batch says what was dropped, not that every voxel is 0
        a = np.zeros((30, 30, 30), np.uint8)
        a[5, 5, 5] = a[20, 20, 20] = 1
        a[10:12, 10:12, 10:12] = 1
        with self.assertRaisesRegex(ValueError, r'segmenting left no grain: 3 specks \(pieces under 27 voxels\)'):
            batch(a, None, segment=True, nSpheres=3, progress=False)

    def test_markers_of_the_user_s_own_are_grown(self):
        scan, truth = porousScan((80, 80, 80), grains=12, size=(10, 16), seed=4)
        from scipy import ndimage
        cores = np.where(ndimage.binary_erosion(truth != 0, iterations=3), truth, 0)  # a seed inside each grain
        labels, info = segmentScan(scan, markers=cores)
        self.assertGreaterEqual(float(np.median(bestOverlap(labels, truth))), 0.9)
        self.assertIn('markers', info['method'])
        with self.assertRaisesRegex(ValueError, 'markers must be an integer volume of the scan'):
            segmentScan(scan, markers=cores[:10])
        with self.assertRaisesRegex(ValueError, r'markers must be labels >= 0 \(0: no marker\), found -1'):
            segmentScan(scan, markers=np.where(cores > 0, -1, 0))


class SkippedGrains(unittest.TestCase):
    def test_no_contact_ball_toward_a_grain_not_generated_and_no_contact_lost_with_it(self):
        # the bug: specks under --min-voxels still got contact balls on their neighbours (5,074 of 5,594 spheres
        # of a real scan's batch), and the report counted their contacts lost
        from yade_mss.specimens import makeTasks
        L = packedSpecimen((40, 40, 40), grains=24, size=(3, 7), seed=7)
        sizes = {r.label: r.voxels for r in regions(L)}
        cut = sorted(sizes.values())[len(sizes) // 3]  # a third of the grains skipped
        tasks, skipped, key, found = makeTasks(L, {'nSpheres': 6}, minVoxels=cut)
        made = set(t.label for t in tasks)
        self.assertTrue(skipped and made)
        withSkipped = [c for c in found if (c['a'] in made) != (c['b'] in made)]
        self.assertTrue(withSkipped, 'the specimen must have contacts between generated and skipped grains')
        for t in tasks:
            want = sum(1 for c in found if t.label in (c['a'], c['b']) and c['a'] in made and c['b'] in made)
            self.assertEqual(len(t.contacts), want, t.label)
        b = batch(L, None, workers=1, progress=False, nSpheres=6, minVoxels=cut)
        others = {int(r['label']): r['contacts_not_generated'] for r in b.rows.values() if r['status'] == 'ok'}
        for c in withSkipped:
            lab = c['a'] if c['a'] in made else c['b']
            self.assertGreater(others[lab], 0)
        import re
        for r in b.rows.values():  # lost: the scan's contacts less those kept and those with grains not generated
            if r['status'] != 'ok':
                continue
            said = re.search(r'(\d+) of its (\d+) contacts in the scan lost', r['problems'])
            lost = r['contacts_ct'] - r['contacts_kept'] - r['contacts_not_generated']
            self.assertEqual(int(said.group(1)) if said else 0, lost, r['problems'])
            if said and r['contacts_not_generated']:
                self.assertIn('(%d more with grains not generated)' % r['contacts_not_generated'], r['problems'])


class LostContacts(unittest.TestCase):
    def test_every_lost_contact_has_its_reason(self):
        # the issue: contacts lost at the volume's border (gap 2) with no reason given
        from yade_mss.specimens._report import LOST_BORDER, LOST_GAP, LOST_REACH, lostReason
        b = batch(packedSpecimen((60, 60, 60), grains=30, seed=1), None, workers=1, progress=False, nSpheres=8,
                  contactGap=2.0, voxelSize=1e-3)
        c = b.contacts
        self.assertGreater(sum(c['lost'].values()), 0)
        self.assertEqual(sum(c['lost'].values()), c['between'] - c['kept'])
        self.assertLessEqual(set(c['lost']), {LOST_BORDER, LOST_GAP, LOST_REACH})
        for r in b.rows.values():
            if r['status'] != 'ok':
                continue
            lost = r['contacts_ct'] - r['contacts_kept'] - r['contacts_not_generated']
            said = sum(int(part.split()[0]) for part in r['contacts_lost_why'].split(', ') if part)
            self.assertEqual(said, lost, r)  # each lost contact of the grain, with its reason
            if lost:
                self.assertIn('lost: ' + r['contacts_lost_why'], r['problems'])
        # a reason of the border only where one of the two grains is cut by it
        byLabel = {r['label']: r for r in b.rows.values()}
        for contact in b.scanContacts:
            ra, rb = byLabel[contact['a']], byLabel[contact['b']]
            why = lostReason(contact, ra, rb)
            self.assertEqual(why == LOST_BORDER, bool(ra['touches_border'] or rb['touches_border']))


class Reruns(unittest.TestCase):
    def test_a_finished_batch_run_again_does_nothing_and_a_change_is_seen(self):
        L = packedSpecimen((40, 40, 40), grains=20, size=(4, 6), seed=4)
        with tempfile.TemporaryDirectory() as d:
            path, out = os.path.join(d, 'labels.npy'), os.path.join(d, 'out')
            np.save(path, L)
            first = batch([path], out, workers=1, progress=False, nSpheres=5, minVoxels=10)
            self.assertFalse(first.upToDate)
            files = {}
            for top, _, names in os.walk(out):
                for n in names:
                    p = os.path.join(top, n)
                    if n != '.mss.lock':  # the folder's lock, taken by each run
                        files[p] = os.stat(p).st_mtime_ns
            again = batch([path], out, workers=1, progress=False, nSpheres=5, minVoxels=10)
            self.assertTrue(again.upToDate)
            self.assertEqual(again.generated, 0)
            self.assertEqual(set(again.rows), set(first.rows))
            self.assertEqual(again.contacts['kept'], first.contacts['kept'])
            for p, t in files.items():  # nothing rewritten
                self.assertEqual(os.stat(p).st_mtime_ns, t, p)
            k = next(iter(first.results))
            np.testing.assert_array_equal(again.results[k].radii, first.results[k].radii)  # read when asked
            self.assertEqual(len(again.scanContacts), len(first.scanContacts))
            # another option: not up to date, the grains made again
            other = batch([path], out, workers=1, progress=False, nSpheres=4, minVoxels=10)
            self.assertFalse(other.upToDate)
            self.assertGreater(other.generated, 0)
            # the input touched: looked at again, each grain reused by the digest of its voxels
            batch([path], out, workers=1, progress=False, nSpheres=4, minVoxels=10)
            os.utime(path)
            touched = batch([path], out, workers=1, progress=False, nSpheres=4, minVoxels=10)
            self.assertFalse(touched.upToDate)
            self.assertEqual(touched.generated, 0)
            # a grain's result swapped in the folder: made again, not reused
            g = os.path.join(out, 'grains')
            keys = sorted(f[:-4] for f in os.listdir(g) if f.endswith('.npz'))
            with open(os.path.join(g, keys[0] + '.npz'), 'rb') as f:
                other0 = f.read()
            with open(os.path.join(g, keys[1] + '.npz'), 'wb') as f:
                f.write(other0)
            swapped = batch([path], out, workers=1, progress=False, nSpheres=4, minVoxels=10)
            self.assertEqual(swapped.generated, 1)
            np.testing.assert_array_equal(swapped.results[keys[1]].radii, other.results[keys[1]].radii)
            with open(os.path.join(out, 'batch.json')) as f:
                meta = json.load(f)
            self.assertEqual(meta['version'], _manifest.VERSION)
            # every file but the manifest and hidden ones (the lock), each in the digest
            self.assertEqual(meta['outputs']['files'], sum(1 for _, _, f in os.walk(out) for n in f
                                                           if not n.startswith('.')) - 1)

    def test_a_rerun_checks_every_file_it_reuses(self):
        """The attack: a grain's CSV copied over another's (or truncated), an edited grain record or manifest, a
        manifest nested too deep: each was trusted, kept and recorded ("up to date" for ever after)."""
        L = packedSpecimen((40, 40, 40), grains=12, size=(4, 6), seed=5)
        with tempfile.TemporaryDirectory() as d:
            path, out = os.path.join(d, 'labels.npy'), os.path.join(d, 'out')
            np.save(path, L)
            run = lambda: batch([path], out, workers=1, progress=False, nSpheres=5, minVoxels=10)  # noqa: E731
            first = run()
            g = os.path.join(out, 'grains')
            keys = sorted(f[:-4] for f in os.listdir(g) if f.endswith('.npz'))
            a, b = keys[0], keys[1]

            def text(k, ext):
                with open(os.path.join(g, k + '.' + ext), 'rb') as f:
                    return f.read()
            good = text(b, 'csv')
            shutil.copy(os.path.join(g, a + '.csv'), os.path.join(g, b + '.csv'))
            again = run()
            self.assertEqual(again.generated, 1)
            self.assertEqual(text(b, 'csv'), good)  # made again, the right file back
            with open(os.path.join(g, a + '.csv'), 'r+b') as f:
                f.truncate(10)
            self.assertEqual(run().generated, 1)
            # an edited record: its row is not copied into grains.csv
            with open(os.path.join(g, a + '.json')) as f:
                meta = json.load(f)
            meta['row']['spheres'], meta['row']['dice'] = 99, 0
            with open(os.path.join(g, a + '.json'), 'w') as f:
                json.dump(meta, f)
            edited = run()
            self.assertEqual(edited.generated, 1)
            self.assertEqual(int(edited.rows[a]['spheres']), int(first.rows[a]['spheres']))
            self.assertNotIn('99', [r['spheres'] for r in rows(out) if r.get('label') == a[6:]])
            # an edited manifest: not up to date, its state rows not given back
            self.assertTrue(run().upToDate)
            with open(os.path.join(out, 'batch.json')) as f:
                meta = json.load(f)
            meta['state']['rows'][a]['spheres'] = 99
            meta['state']['seconds'] = 1234.5
            with open(os.path.join(out, 'batch.json'), 'w') as f:
                json.dump(meta, f)
            after = run()
            self.assertFalse(after.upToDate)
            self.assertEqual(after.generated, 0)  # each grain checked, none made again
            self.assertEqual(after.rows[a]['spheres'], first.rows[a]['spheres'])
            self.assertNotEqual(after.seconds, 1234.5)
            # a manifest nested too deep for the parser: stale, not "maximum recursion depth exceeded"
            with open(os.path.join(out, 'batch.json'), 'w') as f:
                f.write('[' * 100000 + ']' * 100000)
            self.assertFalse(run().upToDate)
            self.assertTrue(run().upToDate)


def rows(outdir):
    with open(os.path.join(outdir, 'grains.csv')) as f:
        return list(csv.DictReader(f))


class OneBatchAFolder(unittest.TestCase):
    def test_a_second_batch_is_refused_at_once_and_a_stale_lock_taken_over(self):
        from yade_mss.base import folderLock
        L = packedSpecimen((30, 30, 30), grains=6, size=(4, 6), seed=6)
        with tempfile.TemporaryDirectory() as d:
            path, out = os.path.join(d, 'labels.npy'), os.path.join(d, 'out')
            np.save(path, L)
            holder = subprocess.Popen([sys.executable, '-c', 'import sys, time\nfrom yade_mss.base import '
                                       'folderLock\nwith folderLock("test", sys.argv[1]):\n    print("held", '
                                       'flush=True)\n    time.sleep(60)', out], stdout=subprocess.PIPE, text=True)
            try:
                self.assertEqual(holder.stdout.readline().strip(), 'held')
                t = time.monotonic()
                with self.assertRaises(RuntimeError) as e:
                    batch([path], out, workers=1, progress=False, nSpheres=4)
                self.assertLess(time.monotonic() - t, 5.0)  # at once, before any work
                self.assertIn('in use by another job (process %d' % holder.pid, str(e.exception))
                self.assertFalse(os.path.exists(os.path.join(out, 'grains')))
            finally:
                holder.kill()
                holder.wait()
            # the holder is gone (killed: its lock file stays): the lock is taken over
            self.assertTrue(os.path.isfile(os.path.join(out, folderLock.NAME)))
            self.assertEqual(len(batch([path], out, workers=1, progress=False, nSpheres=4).failed), 0)
            # two at once from the command line: one runs, the other is refused
            mss = os.environ.get('MSS_BINARY', 'mss')
            out2 = os.path.join(d, 'two')
            procs = [subprocess.Popen([mss, 'batch', path, '-o', out2, '--spheres', str(n), '--workers', '1'],
                                      stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True) for n in (8, 12)]
            results = [p.communicate(timeout=300) + (p.returncode,) for p in procs]
            codes = sorted(r[2] for r in results)
            if codes == [0, 0]:  # the first ended before the second looked: then they ran one after the other
                self.assertTrue(all('in use' not in r[1] for r in results))
            else:
                self.assertEqual(codes, [0, 1], results)
                self.assertIn('in use by another job', ''.join(r[1] for r in results))


class RefusedBeforeAnyWork(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.d = self.dir.name
        self.path = os.path.join(self.d, 'labels.npy')
        np.save(self.path, packedSpecimen((30, 30, 30), grains=6, size=(4, 6), seed=6))

    def tearDown(self):
        self.dir.cleanup()

    def refused(self, out, words, inputs=None):
        with self.assertRaises(ValueError) as e:
            batch(inputs or [self.path], out, workers=1, progress=False, nSpheres=4)
        self.assertIn(words, str(e.exception))
        grains = os.path.join(out, 'grains')
        self.assertFalse(os.path.isdir(grains) and any(n.endswith('.npz') for n in os.listdir(grains)))

    def test_links_however_spelled(self):
        real = os.path.join(self.d, 'real')
        os.mkdir(real)
        os.symlink(real, os.path.join(self.d, 'lnk'))
        for spelled in ('lnk', 'lnk/', 'lnk/.', 'real/../lnk/'):
            with self.subTest(spelled):
                self.refused(os.path.join(self.d, spelled), 'symbolic link')
        self.assertEqual(os.listdir(real), [])

    def test_planted_outputs(self):
        for name, plant in (('grains.csv', 'link'), ('grains/label_1.csv', 'link'), ('assembly.txt', 'folder'),
                            ('grains', 'file')):
            with self.subTest(name):
                out = os.path.join(self.d, 'out_' + name.replace('/', '_'))
                os.makedirs(os.path.dirname(os.path.join(out, name)), exist_ok=True)
                target = os.path.join(self.d, 'victim')
                if plant == 'link':
                    os.symlink(target, os.path.join(out, name))
                elif plant == 'folder':
                    os.mkdir(os.path.join(out, name))
                else:
                    open(os.path.join(out, name), 'w').close()
                self.refused(out, name.split('/')[0] if plant == 'file' else name)
                self.assertFalse(os.path.exists(target))

    def test_an_output_folder_that_is_a_file(self):
        out = os.path.join(self.d, 'afile')
        open(out, 'w').close()
        self.refused(out, 'exists and is not a folder')

    def test_the_input_folder_as_output(self):
        folder = os.path.join(self.d, 'grains_in')
        os.mkdir(folder)
        shutil.copy(os.path.join(DATA, 'octahedron.stl'), folder)
        self.refused(folder, 'is the input folder', inputs=[folder])
        self.refused(folder + '/', 'is the input folder', inputs=[folder])

    def test_no_criterion_before_the_volume_is_read_and_failures_are_not_generated(self):
        # the bugs: no criterion read the volume, then failed every grain; the summary said they were generated
        bad = os.path.join(self.d, 'bad.npy')
        with open(bad, 'wb') as f:
            f.write(b'not a volume')
        with self.assertRaises(ValueError) as e:
            batch([bad], os.path.join(self.d, 'none'), workers=1, progress=False)
        self.assertIn('give at least one termination criterion', str(e.exception))
        self.assertFalse(os.path.exists(os.path.join(self.d, 'none')))
        folder = os.path.join(self.d, 'meshes')
        os.mkdir(folder)
        shutil.copy(os.path.join(DATA, 'octahedron.stl'), folder)
        with open(os.path.join(folder, 'broken.stl'), 'w') as f:
            f.write('solid x\nhello\n')
        mss = os.environ.get('MSS_BINARY', 'mss')
        p = subprocess.run([mss, 'batch', folder, '-o', os.path.join(self.d, 'out'), '--spheres', '4'],
                           capture_output=True, text=True, timeout=300)
        self.assertIn('1 ok, 0 skipped, 1 failed of 2 grains', p.stdout)
        self.assertIn('(1 grain generated in this run', p.stdout)

    def test_the_voxel_edge_and_its_unit_are_said(self):
        # the bug: without --voxel-size a voxel was 1 m without a word (a batch reported a 0.016 s time step)
        mss = os.environ.get('MSS_BINARY', 'mss')
        for extra, said, page in (([], 'voxel edge 1 (no --voxel-size): lengths, masses and the time step are in '
                                    'voxels', 'Voxel edge 1: no --voxel-size was given'),
                                  (['--voxel-size', '2e-5'], 'voxel edge 2e-05 m', 'Voxel edge 2e-05 m')):
            out = os.path.join(self.d, 'v%d' % len(extra))
            p = subprocess.run([mss, 'batch', self.path, '-o', out, '--spheres', '4'] + extra, capture_output=True,
                               text=True, timeout=300)
            self.assertEqual(p.returncode, 0, p.stderr)
            self.assertIn('batch: ' + said, p.stdout)
            with open(os.path.join(out, 'report.html')) as f:
                self.assertIn(page, f.read())

    def test_arguments_by_name(self):
        for kw, kind in ((dict(segment='no'), TypeError), (dict(excludeBorder='no'), TypeError),
                         (dict(minVoxels='5'), TypeError), (dict(voxelSize='abc'), TypeError),
                         (dict(origin=(1, 2)), ValueError), (dict(labels=np.int64(2)), TypeError),
                         (dict(labels=['x']), TypeError)):
            with self.subTest(kw):
                with self.assertRaises(kind) as e:
                    batch([self.path], None, workers=1, progress=False, nSpheres=4, **kw)
                self.assertIn(list(kw)[0], str(e.exception))
        for address in ('tcp://127.0.0.1:87\n86', 'tcp://127.0.0.1', 'http://127.0.0.1:8786', 'tcp://h:99999'):
            with self.assertRaises(ValueError) as e:
                batch([self.path], None, workers=1, progress=False, nSpheres=4, scheduler=address)
            self.assertIn('SCHEME://HOST:PORT', str(e.exception))
        with self.assertRaises(TypeError):
            batch(None, None, nSpheres=4, progress=False)
        with self.assertRaises(ValueError) as e:
            batch(np.array(1), None, nSpheres=4, progress=False)
        self.assertIn('3-D', str(e.exception))
        # one path alone is a list of one, not its characters
        self.assertEqual(len(batch(self.path, None, workers=1, progress=False, nSpheres=4).rows),
                         len(batch([self.path], None, workers=1, progress=False, nSpheres=4).rows))


if __name__ == '__main__':
    unittest.main()
