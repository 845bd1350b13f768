# Figures of the YADE layer: run  yade -n -x bench/yade_figures.py  (prints tables; nothing is asserted here,
# the tests in tests/yade assert the behaviour).
#  1. mass-property errors of the ellipsoid and femur clumps (against the exact ellipsoid, independent mesh sums);
#  2. YADE's clump API on an mssClump clump and on a plain appendClumped clump of the same spheres, side by side;
#  3. creation time per clump for 2000 clumps, ours and plain appendClumped;
#  4. what YADE's own discretization gives (mass vs the union's, time), and what mass='target' adds.
import math
import os
import sys
import tempfile
import time

import numpy as np
import yade.minieigenHP as me
from yade import utils, export, ymport

data = os.environ.get('MSS_DATA', os.path.join('tests', 'data'))
sys.path.insert(0, os.path.join(data, '..', 'yade'))
from clumptools import meshMass, readStlTriangles, relErr, tensor, vec, rot  # noqa: E402
from yade_mss import generate, mssClump, restoreClumpProperties, writeClumps, readClumps  # noqa: E402

RHO = 2000.0
ELL, FEMUR = os.path.join(data, 'ellipsoid_2_1_1.stl'), os.path.join(data, 'human_femur.stl')


def fresh():
    O.reset()
    return O.materials.append(FrictMat(density=RHO))


print('== 1. mass properties of mssClump clumps (mass=target), relative errors')
mat = fresh()
ell = generate(ELL, nSpheres=10, resolution=103)
cid, _ = mssClump(ell, material=mat)
st = O.bodies[cid].state
M = RHO * 4 / 3 * math.pi * 2
exact = np.array([2, 5, 5]) * M / 5
mom = np.sort(np.array(st.inertia))
axis = rot(st.ori)[:, int(np.argmin(np.array(st.inertia)))]
print('ellipsoid 10 vs the exact ellipsoid: mass %.4f%%, principal moments %s%%, long axis off by %.2e degrees'
      ' (the STL is inscribed in the ellipsoid)' % (100 * (st.mass - M) / M,
                                                     np.array2string(100 * (mom - exact) / exact, precision=4),
                                                     math.degrees(math.acos(min(1, abs(axis[0]))))))
for name, path, n in (('ellipsoid', ELL, 10), ('femur', FEMUR, 70)):
    V, c, I = meshMass(readStlTriangles(path))
    r = ell if n == 10 else generate(path, nSpheres=n, resolution=103)
    cid, _ = mssClump(r, material=mat)
    st = O.bodies[cid].state
    print('%-9s %d vs its mesh (independent numpy sums): mass %.1e, centre %.1e (of the size), tensor %.1e'
          % (name, n, abs(st.mass / (RHO * V) - 1), np.linalg.norm(vec(st.pos) - c) / np.ptp(r.centers, axis=0).max(),
             relErr(tensor(st), RHO * I)))
cid, _ = mssClump(ell, mass='union', material=mat)
u = ell.unionMass(resolution=400)
print('ellipsoid 10, mass=union, vs the union at 400 voxels: mass %.4f%%'
      % (100 * (O.bodies[cid].state.mass - RHO * u.volume) / (RHO * u.volume)))

print('\n== 2. YADE\'s clump API, ellipsoid 10 spheres: plain appendClumped clump | mssClump clump '
      '(mass / exact grain mass, unless said)')


def pair():
    mat = fresh()
    ours = mssClump(ell, material=mat)
    plain = O.bodies.appendClumped([utils.sphere(tuple(c + (10, 0, 0)), float(r), material=mat)
                                    for c, r in zip(ell.centers, ell.radii)])
    return ours, plain


def m(cid):
    return O.bodies[cid].state.mass / (RHO * ell.targetMass.volume)


rows = []
(c, ids), (p, pids) = pair()
rows.append(('created', '%.4f, %d members' % (m(p), len(pids)), '%.4f, %d members' % (m(c), len(O.bodies[c].shape.members))))
seq_p, seq_c = [], []
for k in range(8):
    O.bodies.releaseFromClump(pids[k], p)
    O.bodies.releaseFromClump(ids[k], c)
    seq_p.append('%.3f' % m(p))
    seq_c.append('%.3f' % m(c))
rows.append(('releaseFromClump x8 (to 2)', ' '.join(seq_p), ' '.join(seq_c)))
restoreClumpProperties([c])
rows.append(('  then restoreClumpProperties', '-', '%.4f (union of the 2 left)' % m(c)))
(c, ids), (p, pids) = pair()
O.bodies.addToClump([O.bodies.append(utils.sphere((0, 0, 1.5), 0.5))], c)
O.bodies.addToClump([O.bodies.append(utils.sphere((10, 0, 1.5), 0.5))], p)
rows.append(('addToClump (a r=0.5 sphere)', '%.4f' % m(p), '%.4f; restored: union' % m(c)))
(c, ids), (p, pids) = pair()
O.bodies.erase(c)
O.bodies.erase(p)
O.engines = [ForceResetter(), NewtonIntegrator(damping=0, gravity=(0, 0, -9.81))]
O.dt = 1e-3
O.run(10, True)
rows.append(('erase(cid): free members', 'min mass %.3g' % min(O.bodies[i].state.mass for i in pids),
             'min mass %.3g; kinetic energy %.4g J (>= 0)' % (min(O.bodies[i].state.mass for i in ids), utils.kineticEnergy())))
(c, ids), (p, pids) = pair()
O.bodies.erase(c, True)
O.bodies.erase(p, True)
rows.append(('erase(cid, True)', '%d bodies left' % len([b for b in O.bodies if b]), 'both gone'))
for disc in (0, 5, 10, 20):
    (c, ids), (p, pids) = pair()
    O.bodies.updateClumpProperties(discretization=disc)
    a = m(c)
    restoreClumpProperties()
    rows.append(('updateClumpProperties(%d)' % disc, '%.4f' % m(p), '%.4f; restored %.6f' % (a, m(c))))
(c, ids), (p, pids) = pair()
O.materials[0].density /= 10
for i in ids + pids:
    O.bodies[i].state.mass /= 10
O.bodies.updateClumpProperties(discretization=0)
a, b = m(c), m(p)
restoreClumpProperties()
rows.append(('density / 10, updateClumpProperties(0)', '%.4f (exact: 0.1000)' % b, '%.4f; restored %.6f' % (a, m(c))))
with tempfile.TemporaryDirectory() as d:
    (c, ids), (p, pids) = pair()
    O.save(os.path.join(d, 's.yade.gz'))
    O.load(os.path.join(d, 's.yade.gz'))
    rows.append(('O.save / O.load', '%.4f' % m(p), '%.6f' % m(c)))
    O.saveTmp('x')
    O.loadTmp('x')
    rows.append(('saveTmp / loadTmp', '%.4f' % m(p), '%.6f' % m(c)))
    O.engines = [ForceResetter(), VTKRecorder(fileName=os.path.join(d, 'v-'), recorders=['spheres', 'boxes', 'mass'],
                                              iterPeriod=1), NewtonIntegrator()]
    O.run(1, True)
    boxes = open(os.path.join(d, 'v-boxes.0.vtu')).read().count('<Cell')  # no helper body
    rows.append(('VTKRecorder (all but intr*)', '20 spheres written', '20 spheres written, %s box cells' %
                 ('no' if 'NumberOfCells="0"' in open(os.path.join(d, 'v-boxes.0.vtu')).read() else 'SOME')))
    export.textClumps(os.path.join(d, 't.txt'))
    fresh()
    back = ymport.textClumps(os.path.join(d, 't.txt'))
    rows.append(('export/ymport.textClumps', '%.4f' % m(back[1][0]), '%.4f (YADE re-sums)' % m(back[0][0])))
    (c, ids), (p, pids) = pair()
    writeClumps(os.path.join(d, 'w.txt'))
    fresh()
    back = readClumps(os.path.join(d, 'w.txt'))
    rows.append(('writeClumps/readClumps', '%.4f' % m(back[1][0]), '%.6f' % m(back[0][0])))
O.reset()
O.periodic = True
O.cell.hSize = me.Matrix3(30, 0, 0, 0, 30, 0, 0, 0, 30)
mat = O.materials.append(FrictMat(density=RHO))
c, ids = mssClump(ell, material=mat, center=(5, 5, 5))
O.bodies[c].state.vel = me.Vector3(100, 0, 0)
O.engines = [ForceResetter(), NewtonIntegrator(gravity=(0, 0, 0))]
O.dt = 1e-3
O.run(500, True)
rows.append(('periodic cell, 500 steps across it', '-', '%.6f' % m(c)))
w = max(len(r[0]) for r in rows)
for r in rows:
    print('%-*s | %-34s | %s' % (w, r[0], r[1], r[2]))
print('(* VTKRecorder(recorders=[\'all\']) and [\'intr\'] never return in YADE 2023.02a here, plain scenes too)')

print('\n== 3. creation time per clump, 2000 clumps of the ellipsoid\'s 10 spheres (load: %s)'
      % open('/proc/loadavg').read().split()[0])
for label in ('plain appendClumped', 'mssClump (exact)'):
    mat = fresh()
    t0 = time.perf_counter()
    for k in range(2000):
        shift = np.array([5.0 * (k % 50), 5.0 * (k // 50), 0])
        if label.startswith('plain'):
            O.bodies.appendClumped([utils.sphere(tuple(c + shift), float(r), material=mat)
                                    for c, r in zip(ell.centers, ell.radii)])
        else:
            mssClump(ell, material=mat, center=ell.targetMass.centroid + shift)
    dt = time.perf_counter() - t0
    print('%-20s %.0f us per clump (%.2f s for 2000)' % (label, 1e6 * dt / 2000, dt))
t0 = time.perf_counter()
restoreClumpProperties()
print('%-20s %.0f us per clump (all 2000 in one call)' % ('restoreClumpProperties', 1e6 * (time.perf_counter() - t0) / 2000))

print('\n== 4. YADE\'s own discretization (appendClumped(discretization=N)): mass / the union\'s (400 voxels), time')
for name, r in (('ellipsoid 10', ell), ('femur 70', generate(FEMUR, nSpheres=70, resolution=103))):
    u = r.unionMass(resolution=400)
    target = r.targetMass.volume
    parts = []
    for disc in (0, 5, 10, 20, 40):
        mat = fresh()
        t0 = time.perf_counter()
        cid, _ = O.bodies.appendClumped([utils.sphere(tuple(c), float(x), material=mat)
                                         for c, x in zip(r.centers, r.radii)], discretization=disc)
        dt = time.perf_counter() - t0
        parts.append('%d: %+.3f%% %.0f ms' % (disc, 100 * (O.bodies[cid].state.mass / (RHO * u.volume) - 1), 1e3 * dt))
    print('%-13s %s' % (name, ' | '.join(parts)))
    print('%-13s the grain (mass=target) differs from the union by %+.2f%%' % ('', 100 * (target / u.volume - 1)))

print('\n== 5. packings: kinetic energy at step 1000 of a loose packing, no gravity, periodic 0.1 m cell '
      '(overlapping starts explode)')
from yade import pack  # noqa: E402
from yade_mss import mssTemplate, mssClumpCloud, mssReplaceByClumps  # noqa: E402
tpl = mssTemplate(ell, scale=0.004)


def run1000(build):
    O.reset()
    O.periodic = True
    O.cell.hSize = me.Matrix3(0.1, 0, 0, 0, 0.1, 0, 0, 0, 0.1)
    O.materials.append(FrictMat(density=RHO, young=1e7, poisson=0.3, frictionAngle=0.5))
    n = build()
    O.engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb()]),
                 InteractionLoop([Ig2_Sphere_Sphere_ScGeom()], [Ip2_FrictMat_FrictMat_FrictPhys()],
                                 [Law2_ScGeom_FrictPhys_CundallStrack()]),
                 NewtonIntegrator(damping=0.2, gravity=(0, 0, 0))]
    O.dt = 0.5 * utils.PWaveTimeStep()
    O.run(1000, True)
    return n, utils.kineticEnergy()


def spheres():
    sp = pack.SpherePack()
    sp.makeCloud((0, 0, 0), (0.1, 0.1, 0.1), rMean=tpl.boundingRadius, num=100, periodic=True, seed=1)
    sp.toSimulation()


def yadeReplace():
    spheres()
    return len(O.bodies.replaceByClumps([tpl.clumpTemplate], [1.0]))


def ourReplace():
    spheres()
    return len(mssReplaceByClumps([tpl], [1.0], seed=1))


def cloud():
    return len(mssClumpCloud([tpl], (0, 0, 0), (0.1, 0.1, 0.1), num=100, periodic=True, seed=1))


print('bounding radius / equivalent radius of the template: %.3f' % (tpl.boundingRadius / tpl.equivalentRadius))
for label, f in (('O.bodies.replaceByClumps (volume of the sphere)', yadeReplace),
                 ('mssReplaceByClumps (inside the sphere)', ourReplace), ('mssClumpCloud', cloud)):
    n, ek = run1000(f)
    print('%-48s %3d clumps, kinetic energy %.3g J' % (label, n, ek))
