"""The parts that keep a batch of 10^5 grains small and quick, each against what it replaced: the contact index
against contactsByLabel, the packed clumps against the results, the manifest's piecewise digest against the
digest of the whole text, the file thread's order and errors. The figures themselves are bench/batch_scale.py's."""

import hashlib
import json
import os
import signal
import tempfile
import threading
import unittest

import numpy as np

from yade_mss import batch, generate, packedSpecimen
from yade_mss.grains import ContactIndex, ScanContacts, contactsByLabel, findContacts, scanContacts
from yade_mss.specimens import _manifest
from yade_mss.specimens._batch import PackedClumps, _Files, _InOrder, _order
from yade_mss.specimens._report import _gap, _gaps, packed


class ContactsAsColumns(unittest.TestCase):
    def setUp(self):
        self.L = packedSpecimen((40, 40, 40), grains=30, size=(4, 7), seed=2)

    def test_columns_give_the_dicts_and_each_grains_points(self):
        found = scanContacts(self.L, 0.5, (1.0, 2.0, 3.0), None, 1.0)
        dicts = findContacts(self.L, 0.5, (1.0, 2.0, 3.0))
        self.assertGreater(len(dicts), 20)
        self.assertEqual(list(found), dicts)
        self.assertEqual(list(ScanContacts.fromDicts(dicts, 1.0)), dicts)
        keep = found.a % 3 != 0  # contacts with some grains left out, as a batch leaves out the skipped ones
        index, byLabel = ContactIndex(found, keep), contactsByLabel([c for c, k in zip(dicts, keep) if k])
        for label in range(1, int(self.L.max()) + 2):
            want = np.array(byLabel.get(label, []), dtype=float).reshape(-1, 6)
            np.testing.assert_array_equal(index(label), want)  # the same numbers, in the same order


class Packed(unittest.TestCase):
    def test_packed_clumps_hold_what_the_results_hold_in_key_order(self):
        results = {}
        for n, k in enumerate(['label_10', 'label_2', 'label_1', 'label_7']):  # as workers give them
            a = np.zeros((12, 12, 12), dtype=bool)
            a[2:6 + n, 3:9, 2:10] = True
            results[k] = generate(a, nSpheres=3 + n, voxelSize=0.1, origin=(n, 0, 0))
        p = PackedClumps()
        for k, r in results.items():
            p.add(k, r)
        p = p.ordered(_order)
        self.assertEqual(list(p), ['label_1', 'label_2', 'label_7', 'label_10'])
        spheres, offsets = p.packed()
        whole, whereEach = packed({k: results[k] for k in p})
        np.testing.assert_array_equal(spheres, whole)
        np.testing.assert_array_equal(offsets, whereEach)
        masses = p.masses()
        for x, k in enumerate(p):
            m = results[k].targetMass
            np.testing.assert_array_equal(masses[x], np.concatenate([[m.volume], m.centroid, m.inertia.ravel()]))
            np.testing.assert_array_equal(p[k].centers, results[k].centers)
            np.testing.assert_array_equal(p[k].radii, results[k].radii)
            np.testing.assert_array_equal(p[k].targetMass.inertia, results[k].targetMass.inertia)
            self.assertEqual(p[k].targetMass.volume, results[k].targetMass.volume)

    def test_the_cores_gaps_are_the_gaps_of_every_sphere_pair(self):
        # the core's clumpGaps replaced numpy's batched products: each pair's gap against the plain pairwise one
        L = packedSpecimen((40, 40, 40), grains=20, size=(4, 8), seed=6)
        b = batch(L, None, workers=1, nSpheres=6, progress=False)
        spheres, offsets = packed(b.results)
        keys = list(b.results)
        i, j = np.triu_indices(len(keys), 1)
        got = _gaps(spheres, offsets, i, j)
        want = [_gap(b.results[keys[x]], b.results[keys[y]]) for x, y in zip(i, j)]
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-12)
        self.assertTrue((got < 0).any() and (got > 1).any())  # overlapping clumps and clumps far apart
        with self.assertRaisesRegex(ValueError, 'clumpGaps: clump %d of %d' % (len(keys), len(keys))):
            _gaps(spheres, offsets, [0], [len(keys)])
        from yade_mss import _mss
        raw = np.asarray(offsets, dtype=np.int64).tobytes()
        pair = np.zeros(1, dtype=np.int64).tobytes()
        for bad, says in ((spheres.astype(np.float32), 'rows x y z r of float64'),
                          (np.zeros((1, 3)), 'rows x y z r of float64'),
                          (spheres[:, :3], 'a C-contiguous array of float64'),
                          (spheres.tolist(), 'a C-contiguous array of float64')):
            with self.assertRaisesRegex(ValueError, 'clumpGaps: the spheres must be ' + says):
                _mss.clumpGaps(bad, raw, pair, pair)
        with self.assertRaisesRegex(ValueError, 'clumpGaps: the offsets must be the bytes of an array of 8-byte'):
            _mss.clumpGaps(spheres, raw[:-3], pair, pair)

    def test_the_assemblys_pairs_slab_by_slab_are_every_near_pair_once(self):
        # the candidates are found a slab of clumps at a time along x (all at once, 10^5 clumps' were 200 MB):
        # with slabs of 7 clumps, the same pairs as with one slab, each once, and every pair of clumps within
        # the tolerance among them (against the plain pairwise gap)
        from yade_mss.specimens import _report
        L = packedSpecimen((40, 40, 40), grains=30, size=(4, 7), seed=8)
        b = batch(L, None, workers=1, nSpheres=5, progress=False)
        spheres, offsets = packed(b.results)
        keys = list(b.results)
        old = _report.SLAB_CLUMPS
        try:
            found = {}
            for slab in (1 << 13, 7):
                _report.SLAB_CLUMPS = slab
                pairs, gaps = _report._assemblyPairs(spheres, offsets, 1.0)
                found[slab] = dict(zip(map(tuple, pairs.tolist()), gaps.tolist()))
                self.assertEqual(len(found[slab]), len(pairs))  # each once
        finally:
            _report.SLAB_CLUMPS = old
        self.assertEqual(found[7], found[1 << 13])
        within = {(x, y) for x in range(len(keys)) for y in range(x + 1, len(keys))
                  if _gap(b.results[keys[x]], b.results[keys[y]]) <= 1.0}
        self.assertGreater(len(within), 20)
        self.assertTrue(within <= set(found[7]))

    def test_a_batch_with_a_folder_gives_its_results_from_their_files(self):
        L = packedSpecimen((30, 30, 30), grains=8, size=(4, 6), seed=4)
        with tempfile.TemporaryDirectory() as d:
            stored = batch(L, os.path.join(d, 'o'), workers=2, nSpheres=4, progress=False)
            held = batch(L, None, workers=1, nSpheres=4, progress=False)
            self.assertEqual(list(stored.results), list(held.results))
            for k in held.results:
                np.testing.assert_array_equal(stored.results[k].radii, held.results[k].radii)
                self.assertEqual(stored.results[k].metrics['dice'], held.results[k].metrics['dice'])
            self.assertEqual(stored.contacts, held.contacts)  # the same passes over packed spheres
            rows = list(stored.rows.values())  # rows from workers share the batch's key strings (1.3 kB a grain)
            self.assertTrue(all(a is b for a, b in zip(rows[0], rows[-1])))


class InOrder(unittest.TestCase):
    def test_results_are_handed_on_in_the_tasks_order_whatever_order_they_come_in(self):
        # workers finish a few grains out of order: held until those before them are in (packed in key order,
        # no copy of every sphere at the end); a grain without a result (failed) lets the next ones go on
        keys = ['label_%d' % i for i in range(1, 41)]
        rng = np.random.default_rng(3)
        came = [keys[i] for i in np.argsort(np.arange(40) + rng.uniform(0, 4, 40))]  # each a few places off
        self.assertNotEqual(came, keys)
        kept = []
        o = _InOrder(keys, lambda k, r: kept.append((k, r)))
        for k in came:
            o.add(k, None if k == 'label_7' else k.upper())
        o.flush()
        self.assertEqual(kept, [(k, k.upper()) for k in keys if k != 'label_7'])
        # past HELD held (Dask's own order) they go on as they come, none lost
        kept = []
        o = _InOrder(keys, lambda k, r: kept.append(k))
        o.HELD = 5
        for k in reversed(keys):
            o.add(k, k)
        o.flush()
        self.assertEqual(sorted(kept), sorted(keys))
        self.assertEqual(kept[:6], list(reversed(keys))[:6])


class Manifest(unittest.TestCase):
    def test_the_piecewise_digest_is_the_digest_of_the_text_read_back(self):
        rows = {'label_%d' % i: {'dice': 0.1 * i, 'spheres': np.int64(i), 'problems': 'thin; "q"',
                                 'seconds': np.float64(i) / 3, 'n': None} for i in range(700)}
        data = {'version': 3, 'state': {'rows': rows, 'ranked': list(rows), 'timeStep': 1e-5, 'nan': float('nan')},
                'key': {'inputs': [['a', 1, 2]]}}
        whole = json.dumps(json.loads(json.dumps(data, default=str)), sort_keys=True)
        self.assertEqual(_manifest.contentDigest(data), hashlib.sha256(whole.encode()).hexdigest())
        self.assertEqual(json.loads(''.join(_manifest._chunks(data))), json.loads(whole))

    def test_the_manifest_made_once_holds_the_digest_of_its_own_content(self):
        """write() digests the text as it writes it, the sum last: read() takes it (the digest of what it reads
        back) and an edit to any row makes it stale."""
        rows = {'label_%d' % i: {'dice': 0.1 * i, 'spheres': i, 'problems': 'thin; "q"'} for i in range(700)}
        with tempfile.TemporaryDirectory() as d:
            with open(os.path.join(d, 'grains.csv'), 'w') as f:
                f.write('x')
            _manifest.write(d, {'inputs': ['a']}, {'rows': rows}, lambda p, put: put(p))
            meta = _manifest.read(d)
            self.assertIsNotNone(meta)
            self.assertEqual(meta['sum'], _manifest.contentDigest({k: meta[k] for k in ('version', 'key', 'outputs',
                                                                                        'state')}))
            self.assertEqual(meta['state']['rows'], rows)
            self.assertEqual(meta['outputs']['files'], 1)
            self.assertIsNotNone(_manifest.finished(d, {'inputs': ['a']}))
            path = os.path.join(d, _manifest.NAME)
            with open(path) as f:
                text = f.read()
            edited = text.replace('"spheres": 5}', '"spheres": 6}')
            self.assertNotEqual(edited, text)
            with open(path, 'w') as f:
                f.write(edited)
            self.assertTrue(_manifest.read(d) is None)


class TablesAsText(unittest.TestCase):
    """The batch's tables are formatted by the core (_mss.formatRows, formatClumpAssembly): the text is the one
    Python's formatting wrote before, number for number."""

    NUMBERS = np.concatenate([
        np.random.default_rng(1).integers(0, 2 ** 63, 200000, dtype=np.int64).view(np.float64),  # any bits
        np.random.default_rng(2).normal(0, 1, 100000), np.random.default_rng(3).uniform(-1e3, 1e3, 100000),
        [0.0, -0.0, 0.1, 100.0, 1e15, 1e16, 9999999999999998.0, 1e-4, 1e-5, 1.5e-5, 5e-324, 1.7976931348623157e308,
         123456789012345678.0, 1e22, -2.5, np.inf, -np.inf, np.nan]])

    def test_numbers_as_repr_and_as_printf_write_them(self):
        from yade_mss import _mss
        for style, text in (('shortest', repr), ('g17', lambda v: '%.17g' % v)):
            got = _mss.formatRows(b'', 0, self.NUMBERS.tobytes(), 1, style, ' ', '\n').decode().split('\n')[:-1]
            want = [text(float(v)) for v in self.NUMBERS]
            self.assertEqual(len(got), len(want))
            bad = [(w, g) for w, g in zip(want, got) if w != g]
            self.assertEqual(bad, [], style)

    def test_contacts_rows_and_the_assembly_as_python_wrote_them(self):
        from yade_mss import _mss
        rng = np.random.default_rng(4)
        ints = rng.integers(-2 ** 40, 2 ** 40, (500, 3))
        floats = rng.normal(0, 10, (500, 7))
        self.assertEqual(_mss.formatRows(ints.tobytes(), 3, floats.tobytes(), 7, 'shortest', ',', '\r\n'),
                         ''.join(('%d,%d,%d,%r,%r,%r,%r,%r,%r,%r\r\n' % tuple(i + f))
                                 for i, f in zip(ints.tolist(), floats.tolist())).encode())
        spheres = rng.normal(0, 1e-3, (40, 4))
        offsets = np.array([0, 5, 5, 17, 40], dtype=np.int64)
        ids, heads = np.array([3, 9, 12, 1 << 40], dtype=np.int64), rng.normal(0, 1e-9, (4, 10))
        want = ''
        for c in range(4):
            want += ('#mss clump %d density 1 mass %r centroid %r %r %r inertia %r %r %r %r %r %r\n'
                     % ((int(ids[c]),) + tuple(heads[c].tolist())))
            want += ''.join('%r %r %r %r %d\n' % (tuple(s) + (int(ids[c]),))
                            for s in spheres[offsets[c]:offsets[c + 1]].tolist())
        self.assertEqual(_mss.formatClumpAssembly(spheres.tobytes(), offsets.tobytes(), ids.tobytes(),
                                                  heads.tobytes()), want.encode())

    def test_bad_tables_are_refused_with_what_is_wrong(self):
        from yade_mss import _mss
        one = np.zeros(4).tobytes()
        for args, message in (((b'', 0, one, 3, 'shortest', ' ', '\n'), 'are not rows of 0 and 3'),
                              ((b'', 0, one, 1, 'pretty', ' ', '\n'), "style must be 'shortest' or 'g17'"),
                              ((b'', 0, one, 0, 'g17', ' ', '\n'), 'give at least one column'),
                              ((b'', 0, one, 1, 'g17', ', ', '\n'), 'the separator must be one character'),
                              ((b'', 0, b'abc', 1, 'g17', ' ', '\n'), 'the bytes of an array of 8-byte numbers')):
            with self.assertRaises(ValueError) as e:
                _mss.formatRows(*args)
            self.assertIn(message, str(e.exception))
        o = np.array([0, 2], dtype=np.int64).tobytes()
        with self.assertRaises(ValueError) as e:  # one sphere given, the offsets say two
            _mss.formatClumpAssembly(one, o, np.array([1], dtype=np.int64).tobytes(), np.zeros(10).tobytes())
        self.assertIn("clump 0's spheres 0 .. 2 are not within the 1 given, in order", str(e.exception))
        with self.assertRaises(ValueError) as e:
            _mss.formatClumpAssembly(one, o, np.array([1, 2], dtype=np.int64).tobytes(), np.zeros(10).tobytes())
        self.assertIn('2 clumps need 3 offsets and 20 mass numbers', str(e.exception))


class FileThread(unittest.TestCase):
    def test_files_are_written_in_order_and_an_error_reaches_the_batch(self):
        with tempfile.TemporaryDirectory() as d:
            f = _Files()
            for i in range(600):  # more than its queue holds
                f.write(os.path.join(d, 'f%d.bin' % i), b'%d' % i)
            f.close()
            self.assertEqual(sorted(os.listdir(d)), sorted('f%d.bin' % i for i in range(600)))
            with open(os.path.join(d, 'f599.bin'), 'rb') as g:
                self.assertEqual(g.read(), b'599')
            f = _Files()
            f.write(os.path.join(d, 'missing', 'x.bin'), b'x')  # a folder that is not there
            with self.assertRaisesRegex(RuntimeError, 'cannot write'):
                f.close()
            f = _Files()
            f.write(os.path.join(d, 'missing', 'y.bin'), b'y')
            f._thread.join(0.5)
            with self.assertRaisesRegex(RuntimeError, 'cannot write'):
                for i in range(100):  # the next file hears of it
                    f.write(os.path.join(d, 'g%d.bin' % i), b'g')
            f.close()

    def test_a_ctrl_c_anywhere_in_a_write_never_hangs_the_close(self):
        # the bug: SIGINT to `mss batch` alone hung it for good: the interrupt landed inside queue.Queue.put,
        # between a `with lock:`'s acquire and its block, and left the queue's lock held; close() then waited on it
        def interrupt(signum, frame):
            raise KeyboardInterrupt
        old = signal.signal(signal.SIGALRM, interrupt)
        rng = np.random.default_rng(5)
        try:
            with tempfile.TemporaryDirectory() as d:
                for trial in range(300):
                    f = _Files()
                    f.QUEUE = 4  # full at once: the batch waits on it, as on a slow disk
                    signal.setitimer(signal.ITIMER_REAL, float(rng.uniform(1e-5, 2e-3)))
                    try:
                        for i in range(10 ** 6):
                            f.write(os.path.join(d, 'f%d.bin' % (i % 50)), b'x')
                    except KeyboardInterrupt:
                        pass
                    finally:
                        signal.setitimer(signal.ITIMER_REAL, 0)
                    closer = threading.Thread(target=f.close, daemon=True)
                    closer.start()
                    closer.join(10)
                    self.assertFalse(closer.is_alive(), 'close() hung after an interrupt (trial %d)' % trial)
                left = [n for n in os.listdir(d) if n.startswith('.')]
                self.assertEqual(left, [])  # every file written whole or not begun: no temporary file left
        finally:
            signal.signal(signal.SIGALRM, old)


if __name__ == '__main__':
    unittest.main()


class DigestTakenWhereItRuns(unittest.TestCase):
    def test_a_grain_that_cannot_be_read_is_a_failed_row_not_the_batchs_end(self):
        # its digest is taken where it runs; one that fails there (a folder named like a mesh) has none, and the
        # batch records the failure instead of taking the digest again and stopping on it
        data = os.environ['MSS_TEST_DATA']
        mesh = next(f for f in sorted(os.listdir(data)) if f.endswith('.stl'))
        with tempfile.TemporaryDirectory() as d:
            src = os.path.join(d, 'in')
            os.makedirs(os.path.join(src, 'b.stl'))
            with open(os.path.join(data, mesh), 'rb') as f, open(os.path.join(src, 'a.stl'), 'wb') as g:
                g.write(f.read())
            b = batch([src], os.path.join(d, 'out'), nSpheres=4, progress=False, workers=1)
            self.assertEqual(b.rows['file_a.stl']['status'], 'ok')
            self.assertEqual(b.rows['file_b.stl']['status'], 'failed')
            self.assertIn('b.stl', b.rows['file_b.stl']['message'])
