# Triaxial compression of realistic grains: three grains from CT volumes as MSS templates, a periodic packing
# of their clumps (exact mass and inertia each), isotropic compaction, then axial compression at constant
# lateral stress. Prints the stress path.
# Run: yade -n -x examples/triaxial.py        (MSS_SHORT=1 for a short run)
import os

import numpy as np
from yade import utils
from yade_mss import mssTemplate, mssClumpCloud

short = os.environ.get('MSS_SHORT') == '1'
data = os.environ.get('MSS_DATA', os.path.join('tests', 'data'))

# Grains about 2 mm across, 12 spheres each (SI units).
grains = [
    dict(source=os.path.join(data, 'grain_voxels_155x157x167.npy'), voxelSize=2e-3 / 160),
    dict(source=os.path.join(data, 'two_grains_labels.npy'), voxelSize=2e-3 / 60, label=1),
    dict(source=os.path.join(data, 'two_grains_labels.npy'), voxelSize=2e-3 / 70, label=2),
]
from yade_mss import generate
templates = [mssTemplate(generate(g['source'], nSpheres=12, voxelSize=g['voxelSize'], label=g.get('label')))
             for g in grains]
for g, t in zip(grains, templates):
    print('template %-32s %2d spheres, dice %.3f, equivalent radius %.3g mm'
          % (os.path.basename(g['source']) + (' label %d' % g['label'] if 'label' in g else ''), len(t.result),
             t.result.metrics['dice'], t.equivalentRadius * 1e3))

sand = O.materials.append(FrictMat(young=1e8, poisson=0.3, frictionAngle=0.5, density=2650, label='sand'))
L = 0.012 if short else 0.018
O.periodic = True
O.cell.hSize = Matrix3(L, 0, 0, 0, L, 0, 0, 0, L)
clumps = mssClumpCloud(templates, (0, 0, 0), (L, L, L), num=60 if short else 200, periodic=True, seed=1,
                       material=sand)
print('packing      %d clumps, %d spheres, cell %.1f mm' % (len(clumps), sum(len(m) for c, m in clumps), L * 1e3))

p0 = 100e3  # confining stress, Pa
O.engines = [
    ForceResetter(),
    InsertionSortCollider([Bo1_Sphere_Aabb()]),
    InteractionLoop([Ig2_Sphere_Sphere_ScGeom()], [Ip2_FrictMat_FrictMat_FrictPhys()],
                    [Law2_ScGeom_FrictPhys_CundallStrack()]),
    PeriTriaxController(label='triax', goal=(-p0, -p0, -p0), stressMask=7, dynCell=True, maxStrainRate=(200, 200, 200),
                        maxUnbalanced=0.05, relStressTol=0.05, doneHook='compacted()'),
    NewtonIntegrator(damping=0.3),
    PyRunner(command='record()', iterPeriod=200, label='recorder', dead=True),
]
O.dt = 0.5 * utils.PWaveTimeStep()
path = []


def porosity():
    # from the clumps' masses (exact grain volumes); utils.porosity() would sum overlapping spheres
    solid = sum(O.bodies[c].state.mass for c, m in clumps) / O.materials[sand].density
    return 1 - solid / O.cell.volume


def compacted():
    print('compacted    at iteration %d, porosity %.3f' % (O.iter, porosity()))
    # axial compression along z at constant lateral stress
    triax.goal = (-p0, -p0, -0.2)
    triax.stressMask = 3
    triax.maxStrainRate = (200, 200, 20)
    triax.doneHook = ''
    recorder.dead = False
    O.cell.trsf = Matrix3.Identity


def record():
    s = triax.stress
    p = -(s[0] + s[1] + s[2]) / 3
    q = -(s[2] - 0.5 * (s[0] + s[1]))
    path.append((-triax.strain[2], p, q))
    print('strain %6.4f  p %9.1f Pa  q %9.1f Pa  q/p %.3f' % (path[-1][0], p, q, q / p if p > 0 else float('nan')))


stepsCompact = 4000 if short else 40000
O.run(stepsCompact, True)
if recorder.dead:
    print('not compacted after %d steps (short run); compressing anyway' % stepsCompact)
    compacted()
O.run(2000 if short else 20000, True)
if not path or not all(np.isfinite(v) for row in path for v in row):
    raise SystemExit('no stress path recorded')
print('stress path: %d points, final strain %.4f, p %.1f Pa, q %.1f Pa' % (len(path), path[-1][0], path[-1][1], path[-1][2]))
