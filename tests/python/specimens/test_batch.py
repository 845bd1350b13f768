"""mss batch: a labelled specimen or a folder of grains to an assembly, locally, in processes and on a real
Dask cluster started here on localhost (scheduler and two workers, one killed mid-batch)."""
import csv
import json
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time
import unittest

import numpy as np

from yade_mss import batch, readClumps, regions, syntheticSpecimen  # noqa: F401
from yade_mss.cli import batch as batchMain

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..', 'data')
_specimen = []


def specimen():
    """The bar's specimen: 40 grains in 160^3 voxels, 14 of them cut by the border (seed 3)."""
    if not _specimen:
        _specimen.append(syntheticSpecimen((160, 160, 160), 40, seed=3))
    return _specimen[0]


def rows(outdir):
    with open(os.path.join(outdir, 'grains.csv')) as f:
        return list(csv.DictReader(f))


class Cluster(object):
    """A Dask scheduler and two workers (no nanny: a killed worker stays dead) on localhost; with *tls*, every
    connection encrypted and authenticated by a self-signed certificate (Dask's Security.temporary), whose files
    are ``self.tls`` (ca, cert, key)."""

    def __init__(self, tls=False):
        self.useTls = tls

    def __enter__(self):
        self.dir = tempfile.mkdtemp()
        self.file = os.path.join(self.dir, 'scheduler.json')
        env = dict(os.environ)
        tlsArgs = []
        if self.useTls:
            from distributed.security import Security
            sec = Security.temporary()
            cert, key = os.path.join(self.dir, 'cert.pem'), os.path.join(self.dir, 'key.pem')
            with open(cert, 'w') as f:
                f.write(sec.tls_client_cert)
            with open(key, 'w') as f:
                f.write(sec.tls_client_key)
            self.tls = (cert, cert, key)
            tlsArgs = ['--tls-ca-file', cert, '--tls-cert', cert, '--tls-key', key]
        self.procs = [subprocess.Popen(['dask-scheduler', '--host', '127.0.0.1', '--port', '0', '--no-dashboard',
                                        '--scheduler-file', self.file] + tlsArgs
                                       + (['--protocol', 'tls'] if self.useTls else []), stdout=subprocess.DEVNULL,
                                       stderr=subprocess.DEVNULL, env=env)]
        for _ in range(100):
            if os.path.exists(self.file):
                break
            time.sleep(0.1)
        time.sleep(0.5)
        with open(self.file) as f:
            self.address = json.load(f)['address']
        for _ in range(2):
            self.procs.append(subprocess.Popen(['dask-worker', '--scheduler-file', self.file, '--nthreads', '1',
                                                '--no-nanny', '--no-dashboard'] + tlsArgs, stdout=subprocess.DEVNULL,
                                               stderr=subprocess.DEVNULL, env=env))
        from distributed import Client
        from yade_mss.specimens import clusterSecurity
        sec = clusterSecurity(None, *self.tls) if self.useTls else None
        with Client(self.address, timeout=30, security=sec) as c:
            c.wait_for_workers(2, timeout=60)
        return self

    def __exit__(self, *exc):
        for p in self.procs:
            if p.poll() is None:
                p.kill()
            p.wait()
        shutil.rmtree(self.dir, ignore_errors=True)


class Integrity(unittest.TestCase):
    """Nothing of one input is ever taken for another's."""

    def test_a_rerun_on_another_input_does_not_reuse_results(self):
        # the bug: specB after specA into the same folder: "2 done before", B's assembly byte-identical to A's
        A = syntheticSpecimen((40, 40, 40), 2, size=(5, 9), seed=2)
        B = syntheticSpecimen((40, 40, 40), 2, size=(5, 9), seed=5)
        with tempfile.TemporaryDirectory() as d:
            for name, L in (('A', A), ('B', B)):
                np.save(os.path.join(d, 'spec%s.npy' % name), L)
            out = os.path.join(d, 'out')
            batch([os.path.join(d, 'specA.npy')], out, workers=1, nSpheres=5, progress=False)
            a = open(os.path.join(out, 'assembly.txt')).read()
            batch([os.path.join(d, 'specB.npy')], out, workers=1, nSpheres=5, progress=False)
            b = open(os.path.join(out, 'assembly.txt')).read()
            batch([os.path.join(d, 'specB.npy')], os.path.join(d, 'fresh'), workers=1, nSpheres=5, progress=False)
            self.assertNotEqual(a, b)
            self.assertEqual(b, open(os.path.join(d, 'fresh', 'assembly.txt')).read())
            # the same input again is reused (nothing rewritten)
            g = os.path.join(out, 'grains')
            before = {f: os.path.getmtime(os.path.join(g, f)) for f in os.listdir(g) if f.endswith('.npz')}
            time.sleep(0.05)
            batch([os.path.join(d, 'specB.npy')], out, workers=1, nSpheres=5, progress=False)
            self.assertEqual(before, {f: os.path.getmtime(os.path.join(g, f)) for f in before})

    def test_files_sharing_a_name_get_keys_of_their_own(self):
        # the bug: col/a/grain.stl, col/b/grain.stl, col/grain.stl and col/grain.npy shared one key: 1 grain of 4
        with tempfile.TemporaryDirectory() as d:
            col = os.path.join(d, 'col')
            for sub in ('a', 'b'):
                os.makedirs(os.path.join(col, sub))
            shutil.copy(os.path.join(DATA, 'ellipsoid_2_1_1.stl'), os.path.join(col, 'a', 'grain.stl'))
            shutil.copy(os.path.join(DATA, 'cube.stl'), os.path.join(col, 'b', 'grain.stl'))
            shutil.copy(os.path.join(DATA, 'octahedron.stl'), os.path.join(col, 'grain.stl'))
            v = np.zeros((12, 12, 12), dtype=np.uint8)
            v[2:10, 3:9, 2:10] = 1
            np.save(os.path.join(col, 'grain.npy'), v)
            files = [os.path.join(col, 'a', 'grain.stl'), os.path.join(col, 'b', 'grain.stl'),
                     os.path.join(col, 'grain.stl'), os.path.join(col, 'grain.npy')]
            out = os.path.join(d, 'out')
            b = batch(files, out, workers=1, nSpheres=4, resolution=20, progress=False)
            self.assertEqual(len(b.results), 4)
            self.assertEqual(len(set(b.results)), 4)
            self.assertEqual(open(os.path.join(out, 'assembly.txt')).read().count('#mss clump'), 4)

    def test_a_bad_file_in_a_folder_is_recorded_and_the_batch_goes_on(self):
        # the bug: one bad volume in a folder aborted the whole batch
        with tempfile.TemporaryDirectory() as d:
            col = os.path.join(d, 'col')
            os.makedirs(col)
            shutil.copy(os.path.join(DATA, 'cube.stl'), col)
            with open(os.path.join(col, 'broken.npy'), 'wb') as f:
                f.write(b'\x93NUMPY garbage')
            out = os.path.join(d, 'out')
            code = batchMain([col, '-o', out, '--spheres', '4', '--resolution', '20', '--workers', '1'])
            got = {r['file'].split(os.sep)[-1] or r['label']: r for r in rows(out)}
            self.assertEqual(code, 1)
            self.assertEqual(got['broken.npy']['status'], 'failed')
            self.assertIn('broken.npy', got['broken.npy']['message'])
            self.assertEqual(sum(1 for r in got.values() if r['status'] == 'ok'), 1)

    def test_no_more_workers_than_grains(self):
        # the bug: --workers 24 forked 24 processes for 2 grains
        import yade_mss.specimens._batch as B
        asked = []
        real = B._executor

        def spy(workers, scheduler, *rest):
            asked.append(workers)
            return real(workers, scheduler, *rest)
        B._executor = spy
        try:
            with tempfile.TemporaryDirectory() as d:
                L = syntheticSpecimen((40, 40, 40), 2, size=(5, 9), seed=2)
                b = batch(L, os.path.join(d, 'o'), workers=24, nSpheres=3, progress=False)
        finally:
            B._executor = real
        self.assertEqual(asked, [len(b.rows)])
        with self.assertRaises(ValueError):
            batch(L, None, workers=0, nSpheres=3, progress=False)

    def test_hostile_and_non_utf8_names_survive_escaped(self):
        # the bugs: a raw file name in the thumbnail's src ran script; a non-UTF-8 name lost grains.csv
        with tempfile.TemporaryDirectory() as d:
            col = os.path.join(d, 'col')
            os.makedirs(col)
            hostile = 'x" onerror="alert(document.domain).stl'
            shutil.copy(os.path.join(DATA, 'cube.stl'), os.path.join(col, hostile))
            shutil.copy(os.path.join(DATA, 'octahedron.stl'), os.path.join(os.fsencode(col), b'gr\xffain.stl'))
            out = os.path.join(d, 'out')
            b = batch([col], out, workers=1, nSpheres=4, resolution=20, progress=False, previews=True)
            self.assertEqual(len(b.results), 2)
            report = open(os.path.join(out, 'report.html'), encoding='utf-8').read()
            self.assertNotIn('onerror="', report)
            self.assertIn('x&quot; onerror=&quot;alert(document.domain).stl', report)
            table = open(os.path.join(out, 'grains.csv'), encoding='utf-8').read()
            self.assertIn('gr\\udcffain.stl', table)
            self.assertEqual(len(rows(out)), 2)


def processesMentioning(text):
    """Pids of the processes whose command line mentions *text* (a batch's unique output folder)."""
    out = []
    for pid in os.listdir('/proc'):
        if pid.isdigit():
            try:
                with open('/proc/%s/cmdline' % pid, 'rb') as f:
                    if text.encode() in f.read():
                        out.append(int(pid))
            except OSError:
                pass
    return out


def childrenOf(pid):
    try:
        with open('/proc/%d/task/%d/children' % (pid, pid)) as f:
            return [int(x) for x in f.read().split()]
    except OSError:
        return []


def finished(grains):
    """The grains' marks of a finished grain (KEY.json), not a temporary file being written (.KEY.json.*.json:
    a process killed while it wrote one leaves it behind, and the count was off by one)."""
    return [f for f in os.listdir(grains) if f.endswith('.json') and not f.startswith('.')]


def waitForGrains(outdir, n, proc, timeout=120):
    g = os.path.join(outdir, 'grains')
    start = time.time()
    while time.time() - start < timeout and proc.poll() is None:
        if os.path.isdir(g) and len(finished(g)) >= n:
            return True
        time.sleep(0.05)
    return False


class Stopping(unittest.TestCase):
    def test_kill_or_ctrl_c_of_mss_batch_stops_every_process_at_once(self):
        # the bugs: `kill` of mss batch left its Python batch and workers running (19 -> 60 grains after it);
        # Ctrl-C left local workers computing ~12 s and threw their grains away
        mss = os.environ.get('MSS_BINARY', 'mss')
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, 'spec.npy')
            np.save(path, specimen())
            # SIGTERM to mss (kill); SIGINT to its whole process group, as a terminal's Ctrl-C sends it; SIGINT
            # to mss alone (timeout -s INT, job schedulers: once ignored, the batch ran to its end)
            for how in ('SIGTERM', 'SIGINT', 'SIGINT to mss alone'):
                with self.subTest(how):
                    out = os.path.join(d, 'out-kill-test-' + how)
                    proc = subprocess.Popen([mss, 'batch', path, '-o', out, '--spheres', '40', '--workers', '2'],
                                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                                            start_new_session=True)
                    self.assertTrue(waitForGrains(out, 2, proc))
                    t0 = time.monotonic()
                    if how == 'SIGTERM':
                        proc.send_signal(signal.SIGTERM)
                    elif how == 'SIGINT':
                        os.killpg(proc.pid, signal.SIGINT)
                    else:
                        proc.send_signal(signal.SIGINT)
                    while processesMentioning(out) and time.monotonic() - t0 < 10:
                        time.sleep(0.02)
                    gone = time.monotonic() - t0
                    proc.wait(timeout=30)
                    print('%s: every process gone %.2f s after the signal' % (how, gone))
                    self.assertEqual(proc.returncode, 143 if how == 'SIGTERM' else 130)
                    # nothing half-published: no temporary file left, no manifest of a finished run
                    left = [n for top, _, names in os.walk(out) for n in names
                            if n.startswith('.') and n != '.mss.lock']
                    self.assertEqual(left, [])
                    self.assertFalse(os.path.exists(os.path.join(out, 'batch.json')))
                    self.assertEqual(processesMentioning(out), [])
                    self.assertLess(gone, 2.0)  # the bar is a second; CI's machines are loaded
                    done = len(finished(os.path.join(out, 'grains')))
                    time.sleep(1.0)
                    self.assertEqual(done, len(finished(os.path.join(out, 'grains'))))
                    # what was finished is kept: the rerun completes the rest
                    code = subprocess.run([mss, 'batch', path, '-o', out, '--spheres', '40', '--workers', '2'],
                                          capture_output=True, text=True, timeout=600)
                    self.assertEqual(code.returncode, 0, code.stderr)
                    self.assertIn('%d done before' % done, code.stdout)

    def test_a_killed_local_worker_ends_the_batch(self):
        # the bug: a killed worker hung the batch forever (error printed, then no progress for 12 minutes)
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, 'spec.npy')
            np.save(path, specimen())
            out = os.path.join(d, 'out-worker-test')
            proc = subprocess.Popen([sys.executable, '-m', 'yade_mss', 'batch', path, '-o', out, '--spheres', '40',
                                     '--workers', '2'], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
            self.assertTrue(waitForGrains(out, 1, proc))
            workers = childrenOf(proc.pid)
            self.assertGreaterEqual(len(workers), 1)
            os.kill(workers[0], signal.SIGKILL)
            text, _ = proc.communicate(timeout=120)  # it ends
            self.assertEqual(proc.returncode, 1, text)
            failed = [r for r in rows(out) if r['status'] == 'failed']
            self.assertGreater(len(failed), 0)
            self.assertTrue(all('worker process died' in r['message'] for r in failed))
            self.assertEqual(processesMentioning(out), [])


class TlsCluster(unittest.TestCase):
    def test_a_tls_cluster_on_localhost(self):
        # the trust gap: --scheduler spoke to Dask unencrypted and unauthenticated, and Dask moves pickles
        L = syntheticSpecimen((50, 50, 50), 3, size=(6, 10), seed=4)
        with tempfile.TemporaryDirectory() as d, Cluster(tls=True) as c:
            path = os.path.join(d, 'spec.npy')
            np.save(path, L)
            self.assertTrue(c.address.startswith('tls://'))
            ca, cert, key = c.tls
            code = batchMain([path, '-o', os.path.join(d, 'tls'), '--spheres', '4', '--scheduler', c.address,
                              '--tls-ca-file', ca, '--tls-cert', cert, '--tls-key', key])
            self.assertEqual(code, 0)
            local = batch([path], os.path.join(d, 'local'), workers=1, nSpheres=4, progress=False)
            self.assertEqual(len(local.results), len(regions(L)))
            self.assertEqual(open(os.path.join(d, 'tls', 'assembly.txt')).read(),
                             open(os.path.join(d, 'local', 'assembly.txt')).read())  # same results, on TLS
            # half the files, or TLS files with a plain address: refused before anything is sent
            self.assertNotEqual(batchMain([path, '-o', os.path.join(d, 'x'), '--spheres', '4', '--scheduler',
                                           c.address, '--tls-ca-file', ca]), 0)
            with self.assertRaises(ValueError) as ctx:
                from yade_mss.specimens import clusterSecurity
                batch([path], None, nSpheres=4, progress=False, scheduler=c.address.replace('tls://', 'tcp://'),
                      security=clusterSecurity(None, ca, cert, key))
            self.assertIn('tls://', str(ctx.exception))


def browserTitle(page):
    """The title of *page* (a file) after headless Chromium loaded it and ran its scripts (a hostile name's
    onerror=... would change it)."""
    with tempfile.TemporaryDirectory() as profile:
        out = subprocess.run(['chromium', '--headless', '--no-sandbox', '--disable-gpu', '--disable-quic',
                              '--no-first-run', '--disable-background-networking', '--disable-component-update',
                              '--disable-sync', '--user-data-dir=' + profile, '--virtual-time-budget=3000',
                              '--dump-dom', 'file://' + os.path.abspath(page)],
                             capture_output=True, text=True, timeout=120).stdout
    start = out.find('<title>')
    return out[start + 7:out.find('</title>', start)] if start >= 0 else None


class ReportInABrowser(unittest.TestCase):
    def test_hostile_file_names_run_no_script(self):
        # the bug: with --previews the raw file name went into the thumbnail's src: x" onerror="..." ran
        with tempfile.TemporaryDirectory() as d:
            bad = os.path.join(d, 'bad.html')  # the detector itself: a page that does run the payload
            with open(bad, 'w') as f:
                f.write('<!doctype html><title>report</title><img src="none.png" onerror="document.title=\'pwned\'">')
            self.assertEqual(browserTitle(bad), 'pwned')
            col = os.path.join(d, 'col')
            os.makedirs(col)
            for name in ('x" onerror="document.title=\'pwned\'".stl', "y' onerror='document.title=\"pwned\"'.stl",
                         '<img src=z onerror=document.title=1>.stl'):
                shutil.copy(os.path.join(DATA, 'cube.stl'), os.path.join(col, name))
            out = os.path.join(d, 'out')
            b = batch([col], out, workers=1, nSpheres=3, resolution=16, progress=False, previews=True)
            self.assertEqual(len(b.results), 3)
            self.assertEqual(browserTitle(os.path.join(out, 'report.html')), 'mss batch')


class Specimen(unittest.TestCase):
    def test_synthetic_specimen(self):
        L = specimen()
        rs = regions(L)
        self.assertEqual(len(rs), 40)
        self.assertEqual(sum(r.touchesBorder for r in rs), 14)
        self.assertTrue(all(r.voxels > 50 for r in rs))

    def test_bar_forty_grains_locally_in_processes_and_on_dask(self):
        L = specimen()
        h, origin = 0.5, np.array([10.0, -4.0, 2.0])
        with tempfile.TemporaryDirectory() as d:
            np.save(os.path.join(d, 'spec.npy'), L)
            out1, out2, outd = (os.path.join(d, x) for x in ('one', 'two', 'dask'))
            b1 = batch([os.path.join(d, 'spec.npy')], out1, workers=1, nSpheres=12, voxelSize=h, origin=origin,
                       progress=False)
            got = rows(out1)
            self.assertEqual([r['status'] for r in got], ['ok'] * 40)
            self.assertEqual(sum(int(r['touches_border']) for r in got), 14)
            for r in got:
                self.assertLessEqual(float(r['dice']), 0.12)
            # each clump where its label is: the grain's centre of mass is its voxels' centroid, and the
            # spheres' union sits within 2 voxels of it
            for key, res in b1.results.items():
                lab = int(key.split('_')[1])
                idx = np.argwhere(L == lab)
                c = origin + h * idx.mean(axis=0)
                np.testing.assert_allclose(res.targetMass.centroid, c, atol=1e-9)
                self.assertLess(np.linalg.norm(res.unionMass(100).centroid - c), 2 * h)
            # a rerun does nothing but read what is done
            b1b = batch([os.path.join(d, 'spec.npy')], out1, workers=1, nSpheres=12, voxelSize=h, origin=origin,
                        progress=False)
            self.assertLess(b1b.seconds, b1.seconds)
            # processes and Dask give the same spheres
            batch([os.path.join(d, 'spec.npy')], out2, workers=2, nSpheres=12, voxelSize=h, origin=origin,
                  progress=False)
            with Cluster() as cl:
                batch([os.path.join(d, 'spec.npy')], outd, scheduler=cl.address, nSpheres=12, voxelSize=h,
                      origin=origin, progress=False)
            a = open(os.path.join(out1, 'assembly.txt')).read()
            self.assertEqual(a, open(os.path.join(out2, 'assembly.txt')).read())
            self.assertEqual(a, open(os.path.join(outd, 'assembly.txt')).read())
            self.assertEqual(a.count('#mss clump'), 40)
            self.assertIn('report_distributions.png', open(os.path.join(out1, 'report.html')).read())

    def test_large_crops_travel_packed_and_dask_says_nothing(self):
        import pickle
        from yade_mss.specimens import GrainTask
        from yade_mss import voronoiBall
        crop = np.zeros((150, 150, 150), dtype=bool)
        crop[20:130, 30:120, 10:140] = True
        t = GrainTask('label_1', {}, label=1, crop=crop, voxelSize=1.0, origin=[0.0, 0.0, 0.0], neighbours=~crop)
        back = pickle.loads(pickle.dumps(t))
        self.assertLess(len(pickle.dumps(t)), 100000)  # 3.4 MB of voxels
        np.testing.assert_array_equal(back.crop, crop)
        np.testing.assert_array_equal(back.neighbours, ~crop)
        self.assertEqual(back.digest, t.digest)
        # a real batch of large grains on a Dask cluster: no "Large object" warning, no traceback
        L = voronoiBall(90, 6, seed=2)
        with tempfile.TemporaryDirectory() as d:
            np.save(os.path.join(d, 'v.npy'), L)
            with Cluster() as cl:
                p = subprocess.run([sys.executable, '-m', 'yade_mss', 'batch', os.path.join(d, 'v.npy'), '-o',
                                    os.path.join(d, 'out'), '--spheres', '8', '--scheduler', cl.address],
                                   capture_output=True, text=True, timeout=600)
            self.assertEqual(p.returncode, 0, p.stderr)
            self.assertNotIn('Large object', p.stderr)
            self.assertNotIn('Traceback', p.stderr + p.stdout)
            self.assertEqual([r['status'] for r in rows(os.path.join(d, 'out'))], ['ok'] * 6)

    def test_a_worker_killed_mid_batch_loses_nothing(self):
        L = syntheticSpecimen((120, 120, 120), 30, size=(10, 18), seed=5)
        with tempfile.TemporaryDirectory() as d:
            np.save(os.path.join(d, 'spec.npy'), L)
            out = os.path.join(d, 'out')
            with Cluster() as cl:
                env = dict(os.environ)
                p = subprocess.Popen([sys.executable, '-m', 'yade_mss', 'batch', os.path.join(d, 'spec.npy'), '-o', out,
                                      '--spheres', '60', '--scheduler', cl.address], stdout=subprocess.PIPE,
                                     stderr=subprocess.STDOUT, env=env, text=True)
                g = os.path.join(out, 'grains')
                for _ in range(600):  # wait for a few grains, then kill a worker
                    if os.path.isdir(g) and len(finished(g)) >= 3:
                        break
                    time.sleep(0.05)
                done = len(finished(g))
                cl.procs[1].send_signal(signal.SIGKILL)
                text, _ = p.communicate(timeout=600)
            self.assertEqual(p.returncode, 0, text)
            self.assertLess(done, 30)  # it was killed mid-batch
            self.assertEqual([r['status'] for r in rows(out)], ['ok'] * len(regions(L)))

    def test_skips_failures_resume_and_labels(self):
        L = specimen()
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, 'spec.npy')
            np.save(path, L)
            out = os.path.join(d, 'out')
            small = sorted(r.voxels for r in regions(L))[5]
            code = batchMain([path, '-o', out, '--spheres', '8', '--min-voxels', str(small), '--exclude-border',
                              '--workers', '1'])
            got = {r['label']: r for r in rows(out)}
            self.assertEqual(code, 0)
            skipped = [r for r in got.values() if r['status'] == 'skipped']
            self.assertGreaterEqual(len(skipped), 14)
            self.assertTrue(all(r['message'] for r in skipped))
            # resume: grains whose files are gone are done again, and only those
            gone = [lab for lab in got if got[lab]['status'] == 'ok'][:2]
            for lab in gone:
                os.remove(os.path.join(out, 'grains', 'label_%s.json' % lab))
            g = os.path.join(out, 'grains')
            before = {f: os.path.getmtime(os.path.join(g, f)) for f in os.listdir(g) if f.endswith('.npz')}
            time.sleep(0.05)
            b = batch([path], out, workers=1, nSpheres=8, minVoxels=small, excludeBorder=True, progress=False)
            self.assertEqual(len(b.results), sum(1 for r in got.values() if r['status'] == 'ok'))
            rewritten = sorted(f for f, t in before.items() if os.path.getmtime(os.path.join(g, f)) != t)
            self.assertEqual(rewritten, sorted('label_%s.npz' % lab for lab in gone))  # only those were redone
            # a radius bound some grains cannot meet: each reported as too small (never shrunk under it), the
            # batch goes on
            out2 = os.path.join(d, 'fail')
            code = batchMain([path, '-o', out2, '--rmin', '30', '--workers', '1', '--labels', '1,2,3'])
            got2 = rows(out2)
            self.assertEqual([r['status'] for r in got2], ['skipped'] * 3)
            self.assertTrue(all('too small for the radius bound' in r['problems'] for r in got2))
            self.assertTrue(all('exceeds the largest inscribed radius' in r['message'] for r in got2))
            self.assertEqual(code, 0)
            for r in got2:
                self.assertIn('largest inscribed radius', r['message'])
            self.assertFalse(os.path.exists(os.path.join(out2, 'grains', 'label_1.npz')))
            with self.assertRaises(ValueError):
                batch([path], None, labels=[999], nSpheres=3, progress=False)
            with self.assertRaises(TypeError):
                batch([path], None, nSphere=3, progress=False)

    def test_folder_of_meshes_and_a_tiff_stack(self):
        import tifffile
        with tempfile.TemporaryDirectory() as d:
            grains = os.path.join(d, 'grains')
            os.makedirs(grains)
            for f in ('ellipsoid_2_1_1.stl', 'cube.stl'):
                shutil.copy(os.path.join(DATA, f), grains)
            out = os.path.join(d, 'out')
            b = batch([grains], out, workers=1, nSpheres=6, resolution=30, progress=False)
            self.assertEqual(sorted(b.results), ['file_cube.stl', 'file_ellipsoid_2_1_1.stl'])
            self.assertEqual(open(os.path.join(out, 'assembly.txt')).read().count('#mss clump'), 2)
            L = syntheticSpecimen((60, 60, 60), 5, size=(5, 9), seed=2)
            tifffile.imwrite(os.path.join(d, 'spec.tif'), L.astype(np.uint16))
            np.save(os.path.join(d, 'spec.npy'), L)
            a = batch([os.path.join(d, 'spec.tif')], os.path.join(d, 't'), workers=2, nSpheres=5, progress=False,
                      previews=True)
            pngs = sorted(f for f in os.listdir(os.path.join(d, 't', 'grains')) if f.endswith('.png'))
            # the grains worth a look, not every grain: flagged ones worst first, else the three of highest D
            self.assertEqual(pngs, sorted(k + '.png' for k in a.previewed))
            flagged = [k for k in a.ranked if a.rows[k]['status'] == 'ok' and a.kinds[k] == 'flagged']
            self.assertEqual(a.previewed, (flagged or [k for k in a.ranked if k in a.results][:3])[:12])
            self.assertGreater(len(a.previewed), 0)
            self.assertLess(len(a.previewed), len(a.results))
            report = open(os.path.join(d, 't', 'report.html')).read()
            self.assertEqual(report.count('<img src="grains/'), len(a.previewed))
            c = batch([os.path.join(d, 'spec.npy')], os.path.join(d, 'n'), workers=1, nSpheres=5, progress=False)
            self.assertEqual(open(os.path.join(d, 't', 'assembly.txt')).read(),
                             open(os.path.join(d, 'n', 'assembly.txt')).read())
            self.assertEqual(len(a.results), len(regions(L)))


def _peakAnon(cmd, env=None):
    """Runs *cmd* and samples its anonymous memory (RssAnon: the heap, not the file's pages that a map shares with
    the page cache) every 2 ms: (return code, output, peak bytes)."""
    with tempfile.TemporaryFile() as log:
        proc = subprocess.Popen(cmd, stdout=log, stderr=subprocess.STDOUT, env=env)
        peak = 0
        while proc.poll() is None:
            try:
                with open('/proc/%d/status' % proc.pid) as f:
                    for line in f:
                        if line.startswith('RssAnon:'):
                            peak = max(peak, int(line.split()[1]) * 1024)
            except OSError:
                pass
            time.sleep(0.002)
        log.seek(0)
        return proc.returncode, log.read().decode(), peak


class VolumeLargerThanTheLimit(unittest.TestCase):
    """A labelled volume four times --memory-limit: the batch reads it in slabs and by a map, never whole."""
    LIMIT = 0.125  # GiB

    def sparse(self, make):
        """48 cubes of 6^3 voxels in 512^3 int32 (512 MiB, a sparse file), in pairs that share a face,
        and one grain in the last corner, so that every slab is read."""
        a = make((512, 512, 512))
        label = 0
        for i in range(4):
            for j in range(3):
                for k in range(2):
                    x, y, z = 40 + 110 * i, 60 + 140 * j, 50 + 100 * k
                    a[x:x + 6, y:y + 6, z:z + 6] = label + 1
                    a[x + 6:x + 12, y:y + 6, z:z + 6] = label + 2  # its face pair
                    label += 2
        a[-7:-1, -7:-1, -7:-1] = label + 1
        a.flush()
        return label + 1

    def run_batch(self, path, d):
        out = os.path.join(d, 'out')
        self.assertGreaterEqual(os.path.getsize(path), 4 * self.LIMIT * (1 << 30))
        code, text, peak = _peakAnon([sys.executable, '-m', 'yade_mss', 'batch', path, '-o', out, '--spheres', '4',
                                      '--workers', '1', '--memory-limit', str(self.LIMIT)])
        self.assertEqual(code, 0, text)
        return rows(out), peak, text

    def check(self, got, n, peak, text):
        self.assertEqual([r['status'] for r in got], ['ok'] * n)
        self.assertEqual(sum(int(r['contacts_ct']) for r in got), 48)  # 24 pairs, each counted by both grains
        self.assertIn('contacts: 24 pairs of grains within 1 voxel in the scan, 24 between generated grains, 24 of '
                      'them kept', text)
        # a whole copy would be 512 MiB; the slabs are a 128th of the limit
        print('peak anonymous memory %.1f MiB for a volume of 512 MiB' % (peak / 2 ** 20), file=sys.stderr)
        self.assertLess(peak, self.LIMIT * (1 << 30), 'peak anonymous memory %.1f MiB' % (peak / 2 ** 20))

    def test_npy_map(self):
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, 'ct.npy')
            n = self.sparse(lambda shape: np.lib.format.open_memmap(path, 'w+', np.int32, shape))
            got, peak, text = self.run_batch(path, d)
            self.check(got, n, peak, text)

    def test_uncompressed_tiff_map(self):
        import tifffile
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, 'ct.tif')
            n = self.sparse(lambda shape: tifffile.memmap(path, shape=shape, dtype=np.int32))
            got, peak, text = self.run_batch(path, d)
            self.check(got, n, peak, text)

    def test_regions_without_a_list_up_to_the_largest_label(self):
        """Labels up to 2^40 (find_objects wants a list that long: a MemoryError) and a big-endian volume (it would
        copy it whole) are boxed by slabs: the same regions as the labels 1..n."""
        from yade_mss.grains import _volumes as _specimen
        rng = np.random.default_rng(4)
        a = rng.integers(0, 40, (30, 31, 32))
        a[a > 30] = 0
        want = [(r.label, r.box, r.voxels, r.touchesBorder) for r in regions(a)]
        self.assertEqual(len(want), 30)
        big = [(r.label >> 40, r.box, r.voxels, r.touchesBorder) for r in regions(a.astype(np.int64) << 40)]
        self.assertEqual(big, want)
        saved = _specimen.SLAB_VOXELS
        try:
            _specimen.SLAB_VOXELS = 1 << 12  # slabs of 4 layers: boxes that span several slabs merge
            swapped = [(r.label, r.box, r.voxels, r.touchesBorder) for r in regions(a.astype('>i4'))]
        finally:
            _specimen.SLAB_VOXELS = saved
        self.assertEqual(swapped, want)
        self.assertEqual([r.label for r in regions(a.astype('>i4'), only=[3, 7])], [3, 7])


if __name__ == '__main__':
    unittest.main()
