"""mss export: templates for other DEM codes with the grain's exact mass properties, read by the real code
(LIGGGHTS 3.8.0, Debian's liggghts: it inserts the template and reports the mass and inertia it uses)."""
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

import numpy as np

import yade_mss
from yade_mss.base import quaternionMatrix, randomRotation
from yade_mss.exports import MAX_TEMPLATES, liggghtsTemplate, quaternion, seed

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..', 'data')
MSS = os.environ.get('MSS_BINARY', 'mss')

# one template inserted once, the bodies' properties dumped at full precision (compute multisphere)
SCRIPT = """atom_style granular
atom_modify map array
boundary f f f
newton off
communicate single vel yes
units si
region domain block -{L} {L} -{L} {L} -{L} {L} units box
create_box 1 domain
neighbor {skin} bin
neigh_modify delay 0
fix m1 all property/global youngsModulus peratomtype 1e7
fix m2 all property/global poissonsRatio peratomtype 0.3
fix m3 all property/global coefficientRestitution peratomtypepair 1 0.5
fix m4 all property/global coefficientFriction peratomtypepair 1 0.5
pair_style gran model hertz tangential history
pair_coeff * *
timestep 1e-6
include template.in
fix pdd all particledistribution/discrete 32452843 1 mss_template_1 1.0
region ins block -{l} {l} -{l} {l} -{l} {l} units box
fix ins all insert/pack seed 49979693 distributiontemplate pdd insert_every once overlapcheck yes \
particles_in_region 1 region ins ntry_mc 10000
fix ms all multisphere
compute mass all multisphere property masstotal
compute inert all multisphere property inertia
compute ex all multisphere property ex_space
compute ey all multisphere property ey_space
compute ez all multisphere property ez_space
compute xcm all multisphere property xcm
run 1
dump d all local 1 bodies.txt c_mass c_inert[1] c_inert[2] c_inert[3] c_ex[1] c_ex[2] c_ex[3] c_ey[1] c_ey[2] \
c_ey[3] c_ez[1] c_ez[2] c_ez[3] c_xcm[1] c_xcm[2] c_xcm[3]
dump_modify d format "{fmt16}"
dump a all custom 1 atoms.txt id x y z radius
dump_modify a format "%d %.17g %.17g %.17g %.17g"
run 1
"""


def read(path):
    with open(path) as f:
        return f.read()


def runLiggghts(template, size):
    """LIGGGHTS on *template* (the text of the include file): (mass, 3x3 inertia tensor in the template's axes,
    atoms' positions relative to the body's centre of mass, radii, log)."""
    with tempfile.TemporaryDirectory() as d:
        with open(os.path.join(d, 'template.in'), 'w') as f:
            f.write(template)
        with open(os.path.join(d, 'in.test'), 'w') as f:
            f.write(SCRIPT.format(L=20 * size, l=10 * size, skin=0.1 * size, fmt16=' '.join(['%.17g'] * 16)))
        p = subprocess.run(['liggghts', '-in', 'in.test', '-echo', 'none'], cwd=d, capture_output=True, text=True,
                           timeout=600)
        log = p.stdout + p.stderr
        if p.returncode != 0 or 'ERROR' in log:
            raise AssertionError('LIGGGHTS failed:\n' + log[-3000:])
        with open(os.path.join(d, 'bodies.txt')) as f:
            rows = [l.split() for l in f if not l.startswith('ITEM')]
        body = [list(map(float, r)) for r in rows if len(r) == 16]
        with open(os.path.join(d, 'atoms.txt')) as f:
            atoms = [l.split() for l in f]
        i = max(k for k, l in enumerate(atoms) if l[:2] == ['ITEM:', 'ATOMS'])
        xyzr = np.array(sorted((int(a[0]),) + tuple(map(float, a[1:])) for a in atoms[i + 1:]))[:, 1:]
    assert len(body) >= 1, rows
    b = body[-1]
    axes = np.array([b[4:7], b[7:10], b[10:13]])  # rows: ex, ey, ez
    tensor = sum(m * np.outer(e, e) for m, e in zip(b[1:4], axes))
    return b[0], tensor, xyzr[:, :3] - np.array(b[13:16]), xyzr[:, 3], log


class Liggghts(unittest.TestCase):
    """The exported templates inserted by LIGGGHTS: the mass and inertia it uses are ours to 1e-9."""

    @classmethod
    def setUpClass(cls):
        cls.femur = yade_mss.generate(os.path.join(DATA, 'human_femur.stl'), nSpheres=70)
        cls.ellipsoid = yade_mss.generate(os.path.join(DATA, 'ellipsoid_2_1_1.stl'), nSpheres=10)

    def check(self, r, density, frame):
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, 'template.in')
            r.export(path, density=density, frame=frame)
            text = read(path)
        size = float(np.max(np.ptp(r.centers, axis=0)) + 2 * r.radii.max())
        mass, tensor, rel, radii, log = runLiggghts(text, size)
        m = r.targetMass
        ours = density * m.volume
        self.assertAlmostEqual(mass / ours, 1.0, delta=1e-9)
        w, R = m.principal()
        want = np.diag(w) if frame == 'principal' else m.inertia
        np.testing.assert_allclose(tensor, density * want, rtol=0, atol=1e-9 * density * w.max())
        # the spheres where the template puts them: the centre of mass at the origin, in the template's axes
        # (inserted unrotated)
        body = (r.centers - m.centroid) @ (R if frame == 'principal' else np.eye(3))
        order = [int(np.argmin(np.linalg.norm(body - p, axis=1))) for p in rel]
        self.assertEqual(sorted(order), list(range(len(r))))
        np.testing.assert_allclose(rel, body[order], rtol=0, atol=1e-9 * size)
        np.testing.assert_allclose(radii, r.radii[order], rtol=1e-12)
        self.assertIn('inserted 1 particle templates', log)
        return mass, tensor

    def test_femur_principal_and_ellipsoid_generated(self):
        self.check(self.femur, 2650.0, 'principal')
        self.check(self.ellipsoid, 1000.0, 'generated')
        self.check(self.ellipsoid, 7.5, 'principal')

    def test_without_mass_properties_liggghts_estimates_the_union(self):
        """The same template without mass and inertia_tensor: LIGGGHTS' Monte Carlo over the spheres' union
        (ntry 10^6), beside the grain's exact figures (printed for the note)."""
        for name, r in (('femur', self.femur), ('ellipsoid', self.ellipsoid)):
            density = 1000.0
            size = float(np.max(np.ptp(r.centers, axis=0)) + 2 * r.radii.max())
            mass, tensor, _, _, _ = runLiggghts(liggghtsTemplate(r, density, exact=False), size)
            exact = density * r.targetMass.volume
            union = density * r.unionMass(200).volume
            w = np.sort(np.linalg.eigvalsh(tensor))
            ours = density * r.targetMass.principal()[0]
            print('%s: LIGGGHTS Monte Carlo mass %.6g, principal moments %s; the grain\'s exact mass %.6g, '
                  'moments %s; the union on a 200-voxel grid %.6g' % (name, mass, ' '.join('%.5g' % x for x in w),
                                                                       exact, ' '.join('%.5g' % x for x in ours),
                                                                       union), file=sys.stderr)
            self.assertLess(abs(mass / union - 1), 0.01)  # what it estimates is the union, not the grain
            self.assertGreater(abs(mass / exact - 1), 1e-4)


class Command(unittest.TestCase):
    def test_cli_writes_what_python_writes(self):
        with tempfile.TemporaryDirectory() as d:
            out = os.path.join(d, 'e.in')
            p = subprocess.run([MSS, 'export', os.path.join(DATA, 'ellipsoid_2_1_1.stl'), '--spheres', '10',
                                '--density', '2500', '--frame', 'generated', '--type', '1', '-o', out],
                               capture_output=True, text=True)
            self.assertEqual(p.returncode, 0, p.stderr)
            self.assertIn('liggghts template of 10 spheres', p.stdout)
            r = yade_mss.generate(os.path.join(DATA, 'ellipsoid_2_1_1.stl'), nSpheres=10)
            r.export(os.path.join(d, 'p.in'), density=2500, frame='generated')
            cli, py = read(out), read(os.path.join(d, 'p.in'))
            self.assertEqual(cli, py)
            # a saved result exports the same, without generating again
            r.save(os.path.join(d, 'r.npz'))
            p = subprocess.run([MSS, 'export', os.path.join(d, 'r.npz'), '--density', '2500', '--frame',
                                'generated', '-o', os.path.join(d, 'n.in')], capture_output=True, text=True)
            self.assertEqual(p.returncode, 0, p.stderr)
            self.assertEqual(read(os.path.join(d, 'n.in')), py)

    def test_bad_input(self):
        with tempfile.TemporaryDirectory() as d:
            r = yade_mss.generate(os.path.join(DATA, 'ellipsoid_2_1_1.stl'), nSpheres=4)
            r.save(os.path.join(d, 'r.csv'))
            r.save(os.path.join(d, 'r.npz'))
            cases = [
                ([os.path.join(d, 'r.csv')], 1, 'sphere file without its grain'),
                ([os.path.join(d, 'r.npz'), '--spheres', '5'], 1, 'generation options (nSpheres) apply to a grain'),
                ([os.path.join(DATA, 'cube.stl'), '--density', '-1'], 1, 'density'),
                ([os.path.join(DATA, 'cube.stl'), '--format', 'pfc4'], 1, 'format'),
                ([os.path.join(DATA, 'cube.stl'), '--frame', 'body'], 1, 'frame'),
                ([os.path.join(DATA, 'cube.stl'), '--type', '0'], 1, 'type'),
                ([os.path.join(d, 'missing.stl')], 1, 'missing.stl'),
            ]
            for args, code, words in cases:
                p = subprocess.run([MSS, 'export'] + args + ['-o', os.path.join(d, 'x.in')], capture_output=True,
                                   text=True)
                self.assertEqual(p.returncode, code, (args, p.stderr))
                self.assertIn(words, p.stderr, args)
                self.assertNotIn('Traceback', p.stderr)
            self.assertFalse(os.path.exists(os.path.join(d, 'x.in')))
            with self.assertRaises(TypeError):
                r.export(os.path.join(d, 'y.in'), densty=2)
            with self.assertRaises(ValueError):
                r.export(os.path.join(d, 'y.in'), frame='body')
            with self.assertRaises(ValueError):
                r.export(os.path.join(d, 'y.in'), density=float('nan'))
            with self.assertRaises(ValueError) as e:  # templates need a folder to go to
                yade_mss.batch([os.path.join(DATA, 'cube.stl')], None, nSpheres=2, format='kratos', progress=False)
            self.assertIn('give outdir', str(e.exception))
            with self.assertRaises(ValueError):
                yade_mss.batch([os.path.join(DATA, 'cube.stl')], d, nSpheres=2, format='abaqus', progress=False)

    def test_quaternion_and_seeds(self):
        rng = np.random.default_rng(5)
        for R in [randomRotation(rng) for _ in range(500)] + [np.diag(d) for d in ((1, 1, 1), (1, -1, -1),
                                                                                (-1, 1, -1), (-1, -1, 1))]:
            q = quaternion(R)
            self.assertGreaterEqual(q[0], 0)
            np.testing.assert_allclose(quaternionMatrix(q), R, atol=1e-12)
        seeds = [seed(t) for t in range(1, 200)] + [seed(MAX_TEMPLATES)]
        self.assertEqual(len(set(seeds)), len(seeds))
        self.assertLess(seeds[-1], 2 ** 31)
        for n in seeds[:20]:
            self.assertTrue(n > 10000 and all(n % d for d in range(2, int(n ** 0.5) + 1)))
        with self.assertRaises(ValueError):
            seed(MAX_TEMPLATES + 200000)

    def test_a_hostile_file_name_stays_a_comment(self):
        """A grain named with newlines and a LIGGGHTS command: the name is a comment, LIGGGHTS runs nothing else."""
        with tempfile.TemporaryDirectory() as d:
            evil = os.path.join(d, 'e\nshell touch PWNED\n.stl')
            shutil.copy(os.path.join(DATA, 'ellipsoid_2_1_1.stl'), evil)
            r = yade_mss.generate(evil, nSpheres=4)
            text = liggghtsTemplate(r, 1000.0)
            self.assertFalse(any(l.startswith('shell') for l in text.splitlines()))
            self.assertIn('e?shell touch PWNED?.stl', text)
            cwd = os.getcwd()
            try:
                os.chdir(d)
                runLiggghts(text, 10.0)
            finally:
                os.chdir(cwd)
            self.assertFalse(os.path.exists(os.path.join(d, 'PWNED')))
            from yade_mss.exports import kratosCluster
            text = kratosCluster(r)
            head = text.split('\nName\n')[0].splitlines()
            self.assertTrue(all(l.startswith('//') or not l for l in head), head)
            self.assertEqual(text.split('\nName\n')[1].splitlines()[0], 'e_shell_touch_PWNED_')


def readKratos(path):
    """A .clu file read as Kratos' DEM application reads it (ReadClusterFile in its pre-processing: lines
    starting '//' skipped, the keywords' values on the lines after them, the centres taken relative to
    Particle_center_and_diameter's centre)."""
    out = {}
    with open(path) as f:
        lines = [l for l in f.read().splitlines() if not l.startswith('//')]
    it = iter(lines)
    for line in it:
        if line.startswith('Name'):
            out['name'] = next(it).split()[0]
        elif line.startswith('Begin centers_and_radii'):
            rows = []
            for l in it:
                if l.startswith('End centers_and_radii'):
                    break
                rows.append([float(x) for x in l.split()])
            out['spheres'] = np.array(rows)
        elif line.startswith('Particle_center_and_diameter'):
            v = [float(x) for x in next(it).split()]
            out['center'], out['diameter'] = np.array(v[:3]), v[3]
        elif line.startswith('Size'):
            out['size'] = float(next(it).split()[0])
        elif line.startswith('Volume'):
            out['volume'] = float(next(it).split()[0])
        elif line.startswith('Inertia per unit mass'):
            out['inertia'] = np.array([float(next(it).split()[0]) for _ in range(3)])
    out['spheres'][:, :3] -= out['center']
    return out


def readMercury(folder):
    """A clump folder read as MercuryDPM's ClumpInput.h reads it: Clump/Clump.txt (x,y,z,r a line),
    Inertia/Mass.txt, Inertia/TOI.txt and Inertia/PD.txt (three comma-separated values a line); in doubles here
    (MercuryDPM itself parses with std::stof)."""
    def rows(rel, n):
        with open(os.path.join(folder, rel)) as f:
            return np.array([[float(x) for x in l.split(',')[:n]] for l in f if l.strip()])
    with open(os.path.join(folder, 'Inertia', 'Mass.txt')) as f:
        mass = float(f.read().split()[0])
    return rows(os.path.join('Clump', 'Clump.txt'), 4), mass, rows(os.path.join('Inertia', 'TOI.txt'), 3), \
        rows(os.path.join('Inertia', 'PD.txt'), 3)


def readPfc(path):
    """A .p3dat file read as PFC3D's command processor reads ``clump template create`` (its manual): ';' starts
    a comment, '...' continues a line; ``pebbles N`` then N times radius x y z; ``volume V``; ``inertia I11 I22
    I33 I12 I13 I23`` (unit density); ``position x y z``, the clump's centroid, to which PFC translates the
    origin (the pebbles are stored relative to it)."""
    with open(path) as f:
        text = f.read()
    command, commands = '', []
    for line in text.splitlines():
        line = line.split(';')[0].rstrip()
        more = line.endswith('...')
        command += ' ' + (line[:-3] if more else line)
        if not more:
            commands.append(command.split())
            command = ''
    found = [w for w in commands if [x.lower() for x in w[:3]] == ['clump', 'template', 'create']]
    assert len(found) == 1, found
    w, out = found[0], {}
    i = 3
    while i < len(w):
        k = w[i].lower()
        if k == 'name':
            out['name'], i = w[i + 1].strip("'"), i + 2
        elif k == 'pebbles':
            n = int(w[i + 1])
            out['pebbles'] = np.array([float(x) for x in w[i + 2:i + 2 + 4 * n]]).reshape(n, 4)[:, [1, 2, 3, 0]]
            i += 2 + 4 * n
        elif k == 'volume':
            out['volume'], i = float(w[i + 1]), i + 2
        elif k == 'inertia':
            v = [float(x) for x in w[i + 1:i + 7]]
            out['inertia'] = np.array([[v[0], v[3], v[4]], [v[3], v[1], v[5]], [v[4], v[5], v[2]]])
            i += 7
        elif k == 'position':
            out['position'], i = np.array([float(x) for x in w[i + 1:i + 4]]), i + 4
        else:
            raise AssertionError('unknown keyword %r' % w[i])
    out['relative'] = out['pebbles'][:, :3] - out['position']  # as PFC keeps them
    return out


class OtherCodes(unittest.TestCase):
    """Kratos and MercuryDPM templates read back by readers written from those codes' own readers: the spheres
    where they were generated, the mass properties the grain's."""

    @classmethod
    def setUpClass(cls):
        cls.femur = yade_mss.generate(os.path.join(DATA, 'human_femur.stl'), nSpheres=70)

    def world(self, spheres):
        """The template's spheres back where they were generated (c + R p, the header's c and R)."""
        w, R = self.femur.targetMass.principal()
        return spheres[:, :3] @ R.T + self.femur.targetMass.centroid

    def test_kratos_round_trip(self):
        r = self.femur
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, 'femur.clu')
            r.export(path, format='kratos')
            k = readKratos(path)
            text = read(path)
        size = float(np.ptp(r.centers, axis=0).max())
        self.assertEqual(k['name'], 'human_femur')
        np.testing.assert_allclose(self.world(k['spheres']), r.centers, rtol=0, atol=1e-9 * size)
        np.testing.assert_array_equal(k['spheres'][:, 3], r.radii)
        m = r.targetMass
        self.assertEqual(k['volume'], m.volume)
        np.testing.assert_allclose(k['inertia'] * k['volume'], m.principal()[0], rtol=1e-12)
        np.testing.assert_array_equal(k['center'], [0, 0, 0])
        reach = np.linalg.norm(k['spheres'][:, :3], axis=1) + k['spheres'][:, 3]
        self.assertAlmostEqual(k['diameter'], 2 * reach.max(), delta=1e-9 * size)
        self.assertAlmostEqual(k['size'], 2 * (3 * m.volume / (4 * np.pi)) ** (1 / 3), delta=1e-12 * size)
        # the spheres' centre of mass is not the grain's: the file keeps the grain's
        self.assertGreater(np.linalg.norm(r.unionMass(100).centroid - m.centroid), 1e-3 * size)
        self.assertEqual(text.count('\nName\nhuman_femur\n'), 1)
        with self.assertRaises(ValueError):
            r.export(os.path.join(d, 'g.clu'), format='kratos', frame='generated')

    def test_mercurydpm_round_trip_and_folder_rules(self):
        r = self.femur
        with tempfile.TemporaryDirectory() as d:
            out = os.path.join(d, 'femur')
            r.export(out, format='mercurydpm', density=2650)
            pebbles, mass, toi, pd = readMercury(out)
            size = float(np.ptp(r.centers, axis=0).max())
            np.testing.assert_allclose(self.world(pebbles), r.centers, rtol=0, atol=1e-9 * size)
            np.testing.assert_array_equal(pebbles[:, 3], r.radii)
            m = r.targetMass
            self.assertAlmostEqual(mass / (2650 * m.volume), 1, delta=1e-15)
            np.testing.assert_allclose(toi, 2650 * np.diag(m.principal()[0]), rtol=1e-15, atol=0)
            np.testing.assert_array_equal(pd, np.eye(3))
            # what MercuryDPM itself reads: single precision
            self.assertAlmostEqual(float(np.float32(mass)) / mass, 1, delta=1e-7)
            # written again: replaced whole; a folder it did not write, a file or a link there: refused
            r.export(out, format='mercurydpm', density=1000)
            self.assertAlmostEqual(readMercury(out)[1] / (1000 * m.volume), 1, delta=1e-15)
            self.assertEqual(sorted(os.listdir(d)), ['femur'])  # nothing left beside it
            os.makedirs(os.path.join(d, 'mine'))
            open(os.path.join(d, 'mine', 'notes.txt'), 'w').close()
            open(os.path.join(d, 'afile'), 'w').close()
            os.symlink(out, os.path.join(d, 'alink'))
            for name in ('mine', 'afile', 'alink'):
                with self.assertRaises(RuntimeError) as e:
                    r.export(os.path.join(d, name), format='mercurydpm')
                self.assertIn('not replaced', str(e.exception))
            self.assertEqual(os.listdir(os.path.join(d, 'mine')), ['notes.txt'])
            self.assertEqual(sorted(os.listdir(d)), ['afile', 'alink', 'femur', 'mine'])
            with self.assertRaises(ValueError):
                r.export(os.path.join(d, 'g'), format='mercurydpm', frame='generated')

    def test_pfc_round_trip_both_frames(self):
        r = self.femur
        m = r.targetMass
        size = float(np.ptp(r.centers, axis=0).max())
        with tempfile.TemporaryDirectory() as d:
            r.export(os.path.join(d, 'p.p3dat'), format='pfc')
            r.export(os.path.join(d, 'g.p3dat'), format='pfc', frame='generated')
            p, g = readPfc(os.path.join(d, 'p.p3dat')), readPfc(os.path.join(d, 'g.p3dat'))
        self.assertEqual(p['name'], 'human_femur')
        for t in (p, g):
            self.assertEqual(t['volume'], m.volume)
            np.testing.assert_array_equal(t['pebbles'][:, 3], r.radii)
        # principal: the pebbles about the origin in the principal axes, the inertia diagonal
        np.testing.assert_array_equal(p['position'], [0, 0, 0])
        np.testing.assert_allclose(self.world(p['relative']), r.centers, rtol=0, atol=1e-9 * size)
        np.testing.assert_array_equal(p['inertia'], np.diag(m.principal()[0]))
        # generated: the pebbles where they were generated, the position the grain's centroid (not the
        # pebbles'), the inertia the grain's in world axes
        np.testing.assert_array_equal(g['pebbles'][:, :3], r.centers)
        np.testing.assert_array_equal(g['position'], m.centroid)
        np.testing.assert_allclose(g['inertia'], m.inertia, rtol=1e-15, atol=1e-15 * np.abs(m.inertia).max())
        self.assertGreater(np.linalg.norm(r.unionMass(100).centroid - m.centroid), 1e-3 * size)

    def test_a_clumps_file_is_read_within_bounds(self):
        """readClumps' parser refuses a FIFO by name (it would block) and a file over its bound before reading
        it whole (it read any size)."""
        from unittest import mock
        from yade_mss.exports import _yadetext, parseClumps
        with tempfile.TemporaryDirectory() as d:
            fifo = os.path.join(d, 'clumps.txt')
            os.mkfifo(fifo)
            with self.assertRaisesRegex(ValueError, 'readClumps: .*clumps.txt: not a regular file \\(a FIFO\\)'):
                parseClumps(fifo)
            big = os.path.join(d, 'big.txt')
            with open(big, 'w') as f:
                f.write('0 0 0 1 0\n' * 100)
            with mock.patch.object(_yadetext, 'MAX_CLUMP_FILE_BYTES', 500):
                with self.assertRaisesRegex(ValueError, 'readClumps: .*big.txt: over 500 bytes'):
                    parseClumps(big)
            self.assertEqual(len(parseClumps(big)[0][0]), 100)

    def test_yade_clumps_round_trip(self):
        """The yade format is the clumps file of writeClumps: readClumps' own parser takes it (the real YADE
        reading is tests/yade/test_export_yade.py)."""
        from yade_mss.exports import parseClumps as _parse
        r = self.femur
        m = r.targetMass
        size = float(np.ptp(r.centers, axis=0).max())
        with tempfile.TemporaryDirectory() as d:
            for frame in ('principal', 'generated'):
                path = os.path.join(d, frame + '.txt')
                r.export(path, format='yade', density=2650, frame=frame)
                groups, headers = _parse(path)
                self.assertEqual(list(groups), [0])
                a = np.array(groups[0])
                h = headers[0]
                self.assertEqual(h[0], 2650)
                self.assertAlmostEqual(h[1] / (2650 * m.volume), 1, delta=1e-15)
                np.testing.assert_array_equal(h[2:5], [0, 0, 0])
                xx, yy, zz, xy, xz, yz = h[5:]
                I = np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]]) / 2650
                if frame == 'principal':
                    np.testing.assert_allclose(I, np.diag(m.principal()[0]), rtol=1e-15)
                    np.testing.assert_allclose(self.world(a), r.centers, rtol=0, atol=1e-9 * size)
                else:
                    np.testing.assert_allclose(I, m.inertia, rtol=1e-14, atol=1e-15 * np.abs(m.inertia).max())
                    np.testing.assert_allclose(a[:, :3] + m.centroid, r.centers, rtol=0, atol=1e-12 * size)
                np.testing.assert_array_equal(a[:, 3], r.radii)

    def test_read_back_and_compared_where_generated(self):
        """readSpheres and mss compare read every template written here, the spheres back where the grain is
        (the header's c and R): the same D as the spheres' own file."""
        r = self.femur
        with tempfile.TemporaryDirectory() as d:
            paths = [os.path.join(d, 'f.csv')]
            r.save(paths[0])
            for fmt, name in (('liggghts', 'f.in'), ('kratos', 'f.clu'), ('mercurydpm', 'f_clump'), ('pfc', 'f.p3dat'),
                              ('yade', 'f.txt')):
                paths.append(os.path.join(d, name))
                r.export(paths[-1], format=fmt)
                back = yade_mss.readSpheres(paths[-1])
                np.testing.assert_allclose(back.centers, r.centers, rtol=0, atol=1e-12 * np.ptp(r.centers))
                np.testing.assert_array_equal(back.radii, r.radii)
            p = subprocess.run([MSS, 'compare', os.path.join(DATA, 'human_femur.stl')] + paths, capture_output=True,
                               text=True)
            self.assertEqual(p.returncode, 0, p.stderr)
            rows = [l.split() for l in p.stdout.splitlines() if l.split() and l.split()[0] in paths]
            self.assertEqual(len(rows), 6, p.stdout)
            self.assertEqual(len({tuple(x[1:]) for x in rows}), 1, p.stdout)  # every figure the same
            self.assertLess(float(rows[0][2]), 0.05)

    def test_cli_formats(self):
        with tempfile.TemporaryDirectory() as d:
            for fmt, out in (('kratos', 'e.clu'), ('mercurydpm', 'e_clump'), ('pfc', 'e.p3dat'), ('yade', 'e.txt')):
                p = subprocess.run([MSS, 'export', os.path.join(DATA, 'ellipsoid_2_1_1.stl'), '--spheres', '10',
                                    '--format', fmt, '-o', os.path.join(d, out)], capture_output=True, text=True)
                self.assertEqual(p.returncode, 0, p.stderr)
                self.assertIn('%s template of 10 spheres' % fmt, p.stdout)
            self.assertEqual(len(readKratos(os.path.join(d, 'e.clu'))['spheres']), 10)
            self.assertEqual(len(readMercury(os.path.join(d, 'e_clump'))[0]), 10)
            self.assertEqual(len(readPfc(os.path.join(d, 'e.p3dat'))['pebbles']), 10)
            self.assertEqual(len(yade_mss.readSpheres(os.path.join(d, 'e.txt'))), 10)


class Surface(unittest.TestCase):
    """mss surface and MssResult.surface: the union's boundary closed, outward and within the tolerance of the
    union's exact volume, which the grid integration confirms; read by mss info as closed."""

    @classmethod
    def setUpClass(cls):
        cls.femur = yade_mss.generate(os.path.join(DATA, 'human_femur.stl'), nSpheres=70)

    def test_femur_seventy_closed_and_within_half_a_percent(self):
        r = self.femur
        exact = r.unionVolume()
        self.assertAlmostEqual(r.unionMass(300).volume / exact, 1, delta=1e-4)  # an independent integration
        with tempfile.TemporaryDirectory() as d:
            spheres = os.path.join(d, 'femur.csv')
            r.save(spheres)
            out = os.path.join(d, 'femur_surface.stl')
            p = subprocess.run([MSS, 'surface', spheres, '-o', out], capture_output=True, text=True, timeout=600)
            self.assertEqual(p.returncode, 0, p.stderr)
            said = dict(l.split(None, 1) for l in p.stdout.splitlines())
            self.assertEqual(float(said['spheres']), 70)
            info = subprocess.run([MSS, 'info', out], capture_output=True, text=True, timeout=600)
            self.assertEqual(info.returncode, 0, info.stderr)
            got = dict(l.split(None, 1) for l in info.stdout.splitlines())
            self.assertEqual(got['closed'].strip(), 'yes')
            self.assertEqual(got['oriented'].strip(), 'yes')
            self.assertEqual(int(got['self_intersections']), 0)
            self.assertLess(abs(float(got['volume']) / exact - 1), 0.005)
            self.assertLess(abs(float(got['volume']) / exact - 1), 0.002 + 1e-6)  # the default tolerance (STL: floats)
            # the same from Python, and from the LIGGGHTS template (the spheres put back where generated)
            s = r.surface(os.path.join(d, 'f.ply'))
            self.assertEqual(len(s.triangles), int(got['triangles']))
            self.assertLess(abs(s.volume / exact - 1), 0.002)
            self.assertEqual(s.unionVolume, exact)
            back = yade_mss._mss.readMesh(os.path.join(d, 'f.ply'))
            np.testing.assert_array_equal(np.reshape(back[0], (-1, 3)), s.vertices)
            r.export(os.path.join(d, 't.in'))
            p = subprocess.run([MSS, 'surface', os.path.join(d, 't.in'), '-o', os.path.join(d, 't.obj'),
                                '--tolerance', '0.01'], capture_output=True, text=True, timeout=600)
            self.assertEqual(p.returncode, 0, p.stderr)
            said = dict(l.split(None, 1) for l in p.stdout.splitlines())
            self.assertLess(abs(float(said['volume_error'])), 0.01)
            self.assertLess(int(said['triangles']), len(s.triangles))  # a looser bound, fewer triangles
            self.assertAlmostEqual(float(said['union_volume'].split()[0]) / exact, 1, delta=1e-7)

    def test_errors_name_the_problem(self):
        r = self.femur
        with tempfile.TemporaryDirectory() as d:
            spheres = os.path.join(d, 'f.csv')
            r.save(spheres)
            two = os.path.join(d, 'two.txt')
            with open(two, 'w') as f:
                f.write('0 0 0 1 0\n1 0 0 1 0\n5 0 0 1 1\n')
            cases = [([spheres, '-o', os.path.join(d, 'x.off')], "unknown mesh extension '.off'"),
                     ([spheres, '-o', os.path.join(d, 'x.stl'), '--tolerance', '0'], '--tolerance'),
                     ([spheres, '-o', os.path.join(d, 'x.stl'), '--max-triangles', '100'], 'has 4960 triangles, more'),
                     ([spheres, '-o', os.path.join(d, 'x.stl'), '--max-triangles', '10000'],
                      'more than maxTriangles (10000)'),
                     ([spheres, '-o', os.path.join(d, 'x.stl'), '--tolerence', '0.1'], "did you mean '--tolerance'"),
                     ([two, '-o', os.path.join(d, 'x.stl')], 'clump'),
                     ([os.path.join(d, 'missing.csv'), '-o', os.path.join(d, 'x.stl')], 'missing.csv')]
            for args, words in cases:
                p = subprocess.run([MSS, 'surface'] + args, capture_output=True, text=True, timeout=600)
                self.assertIn(p.returncode, (1, 2), args)
                self.assertIn(words, p.stderr, args)
            self.assertFalse(os.path.exists(os.path.join(d, 'x.stl')))
            p = subprocess.run([MSS, 'surface', two, '--clump', '1', '-o', os.path.join(d, 'one.stl')],
                               capture_output=True, text=True, timeout=600)
            self.assertEqual(p.returncode, 0, p.stderr)
            self.assertIn('spheres       1', p.stdout)
            with self.assertRaises(TypeError):
                r.surface(tolerence=0.1)
            with self.assertRaises(ValueError):
                r.surface(tolerance=0.5)
            with self.assertRaises(ValueError):
                r.surface(os.path.join(d, 'x.off'), tolerance=0.1)


class GenerateWritesTemplates(unittest.TestCase):
    """mss generate -o T.clu|T.p3dat and MssResult.save: the templates that take no density, as mss export
    writes them; an option a template cannot take is refused by name."""

    def test_generate_and_save(self):
        grain = os.path.join(DATA, 'ellipsoid_2_1_1.stl')
        r = yade_mss.generate(grain, nSpheres=10)
        with tempfile.TemporaryDirectory() as d:
            for out, read in (('e.clu', lambda p: readKratos(p)['volume']), ('e.p3dat', lambda p: readPfc(p)['volume'])):
                path = os.path.join(d, out)
                p = subprocess.run([MSS, 'generate', grain, '--spheres', '10', '--resolution', '100', '--threads', '1',
                                    '-o', path], capture_output=True, text=True, timeout=600)
                self.assertEqual(p.returncode, 0, p.stderr)
                self.assertIn('template of 10 spheres', p.stdout)
                self.assertEqual(read(path), r.targetMass.volume)
                with open(path) as f:
                    cli = f.read()
                r.save(os.path.join(d, 'saved' + out[1:]))
                with open(os.path.join(d, 'saved' + out[1:])) as f:
                    self.assertEqual(f.read(), cli)  # the same file both ways
            p = subprocess.run([MSS, 'generate', grain, '--spheres', '10', '--clip', '--plane', '0,0,0,1,0,0', '-o',
                                os.path.join(d, 'half.p3dat')], capture_output=True, text=True, timeout=600)
            self.assertEqual(p.returncode, 0, p.stderr)
            half = readPfc(os.path.join(d, 'half.p3dat'))
            self.assertAlmostEqual(half['volume'] / r.targetMass.volume, 0.5, delta=1e-3)  # the plane's half
            p = subprocess.run([MSS, 'generate', grain, '--spheres', '10', '--preview', os.path.join(d, 'x.png'),
                                '-o', os.path.join(d, 'x.clu')], capture_output=True, text=True, timeout=600)
            self.assertEqual(p.returncode, 1)
            self.assertIn('--preview does not apply to a template', p.stderr)
            self.assertFalse(os.path.exists(os.path.join(d, 'x.clu')))
            p = subprocess.run([MSS, 'generate', grain, '--spheres', '10', '-o', os.path.join(d, 'x.in')],
                               capture_output=True, text=True, timeout=600)
            self.assertEqual(p.returncode, 1)
            self.assertIn('.clu (Kratos) or .p3dat (PFC)', p.stderr)


class BatchTemplates(unittest.TestCase):
    """mss batch --format: a template per grain and placements.csv; LIGGGHTS inserts them all with our masses,
    and the placements put each template's spheres back where its grain lies."""

    def test_specimen_templates(self):
        import csv
        L = yade_mss.voronoiBall(16, 3, seed=2)
        with tempfile.TemporaryDirectory() as d:
            np.save(os.path.join(d, 'v.npy'), L)
            out = os.path.join(d, 'out')
            p = subprocess.run([MSS, 'batch', os.path.join(d, 'v.npy'), '-o', out, '--spheres', '6', '--workers', '1',
                                '--format', 'liggghts', '--density', '2500'], capture_output=True, text=True)
            self.assertEqual(p.returncode, 0, p.stderr)
            with open(os.path.join(out, 'placements.csv')) as f:
                place = list(csv.DictReader(f))
            self.assertEqual([r['grain'] for r in place], ['label_1', 'label_2', 'label_3'])
            self.assertEqual(sorted(os.listdir(os.path.join(out, 'templates'))),
                             ['label_1.in', 'label_2.in', 'label_3.in', 'mss_export.txt', 'templates.in'])
            # LIGGGHTS, run in the batch's folder, takes the three templates (types 1-3, seeds all different)
            script = SCRIPT.format(L=200, l=100, skin=1, fmt16='%.17g').replace(
                'include template.in', 'include templates/templates.in').replace(
                'particledistribution/discrete 32452843 1 mss_template_1 1.0',
                'particledistribution/discrete 32452843 3 mss_template_1 0.25 mss_template_2 0.25 mss_template_3 0.5'
            ).replace('particles_in_region 1', 'particles_in_region 30')
            script = script[:script.index('compute inert')] + ('compute ct all multisphere property clumptype\nrun 1\n'
                                                              'dump d all local 1 bodies.txt c_mass c_ct\n'
                                                              'dump_modify d format "%.17g %.17g"\nrun 1\n')
            with open(os.path.join(out, 'in.specimen'), 'w') as f:
                f.write(script)
            run = subprocess.run(['liggghts', '-in', 'in.specimen', '-echo', 'none'], cwd=out, capture_output=True,
                                 text=True, timeout=600)
            self.assertEqual(run.returncode, 0, run.stdout[-3000:])
            bodies, entries = [], False
            with open(os.path.join(out, 'bodies.txt')) as f:
                for l in f:  # the rows after each ITEM: ENTRIES (not the box's bounds)
                    entries = l.startswith('ITEM: ENTRIES') or (entries and not l.startswith('ITEM'))
                    if entries and not l.startswith('ITEM'):
                        bodies.append(l.split())
            masses = {int(float(t)): float(m) for m, t in bodies}
            self.assertEqual(sorted(masses), [1, 2, 3])
            for r in place:
                self.assertAlmostEqual(masses[int(r['type'])] / float(r['mass']), 1, delta=1e-12)
            # the placements put the templates' spheres where the grains are (Kratos clusters: no header used)
            b = yade_mss.batch([os.path.join(d, 'v.npy')], out, nSpheres=6, workers=1, progress=False,
                               format='kratos', density=2500)
            self.assertEqual(sorted(os.listdir(os.path.join(out, 'templates'))),
                             ['label_1.clu', 'label_2.clu', 'label_3.clu', 'mss_export.txt'])  # none of the last run
            with open(os.path.join(out, 'placements.csv')) as f:
                place = list(csv.DictReader(f))
            for r in place:
                k = readKratos(os.path.join(out, r['template']))
                R = quaternionMatrix([float(r[q]) for q in ('qw', 'qx', 'qy', 'qz')])
                c = np.array([float(r[a]) for a in 'xyz'])
                res = b.results[r['grain']]
                np.testing.assert_allclose(k['spheres'][:, :3] @ R.T + c, res.centers, rtol=0, atol=1e-9)
                np.testing.assert_array_equal(k['spheres'][:, 3], res.radii)
            # PFC and the YADE clumps file: the same placements, the templates' own centroid at the origin
            for fmt, ext in (('pfc', '.p3dat'), ('yade', '.txt')):
                b = yade_mss.batch([os.path.join(d, 'v.npy')], out, nSpheres=6, workers=1, progress=False,
                                   format=fmt, density=2500)
                with open(os.path.join(out, 'placements.csv')) as f:
                    place = list(csv.DictReader(f))
                self.assertEqual(sorted(os.listdir(os.path.join(out, 'templates'))),
                                 ['label_1' + ext, 'label_2' + ext, 'label_3' + ext, 'mss_export.txt'])
                for r in place:
                    path = os.path.join(out, r['template'])
                    res = b.results[r['grain']]
                    if fmt == 'pfc':
                        t = readPfc(path)
                        p, rad = t['relative'], t['pebbles'][:, 3]
                        self.assertAlmostEqual(t['volume'] * 2500 / float(r['mass']), 1, delta=1e-15)
                    else:
                        from yade_mss.exports import parseClumps as _parse
                        groups, headers = _parse(path)
                        a = np.array(groups[0])
                        p, rad = a[:, :3], a[:, 3]
                        self.assertEqual(headers[0][1], float(r['mass']))
                    R = quaternionMatrix([float(r[q]) for q in ('qw', 'qx', 'qy', 'qz')])
                    c = np.array([float(r[a]) for a in 'xyz'])
                    np.testing.assert_allclose(p @ R.T + c, res.centers, rtol=0, atol=1e-9)
                    np.testing.assert_array_equal(rad, res.radii)


if __name__ == '__main__':
    unittest.main()
