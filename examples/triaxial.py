# Triaxial compression of realistic grains: three grains from CT volumes as MSS templates, a periodic packing
# of their clumps (exact mass and inertia each), isotropic compaction, then axial compression at constant
# lateral stress up to the goal strain. Prints the stress path from the start of shearing.
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
goal = 0.02 if short else 0.15  # axial strain at which shearing stops
O.engines = [
    ForceResetter(),
    InsertionSortCollider([Bo1_Sphere_Aabb()]),
    InteractionLoop([Ig2_Sphere_Sphere_ScGeom()], [Ip2_FrictMat_FrictMat_FrictPhys()],
                    [Law2_ScGeom_FrictPhys_CundallStrack()]),
    PeriTriaxController(label='triax', goal=(-p0, -p0, -p0), stressMask=7, dynCell=True, maxStrainRate=(200, 200, 200),
                        maxUnbalanced=0.2 if short else 0.05, relStressTol=0.05, doneHook='compacted()'),
    NewtonIntegrator(damping=0.3),
]
O.dt = 0.5 * utils.PWaveTimeStep()
state = {'compacted': False}


def porosity():
    # from the clumps' masses (exact grain volumes); utils.porosity() would sum overlapping spheres
    solid = sum(O.bodies[c].state.mass for c, m in clumps) / O.materials[sand].density
    return 1 - solid / O.cell.volume


def compacted():
    state['compacted'] = True
    triax.doneHook = ''


def stresses():
    s = triax.stress
    p = -(s[0] + s[1] + s[2]) / 3
    q = -(s[2] - 0.5 * (s[0] + s[1]))
    return p, q


# 1. isotropic compaction to p0, in chunks until the controller says it is done
stepsCompact = 40000
while not state['compacted'] and O.iter < stepsCompact:
    O.run(200, True)
print('compacted%s at iteration %d, porosity %.3f, p %.1f Pa'
      % ('' if state['compacted'] else ' NOT', O.iter, porosity(), stresses()[0]))
if not state['compacted'] or abs(stresses()[0] / p0 - 1) > 0.05:
    raise SystemExit('compaction did not reach p = %g Pa within 5%% in %d steps (p %.1f Pa)'
                     % (p0, stepsCompact, stresses()[0]))

# 2. axial compression along z at constant lateral stress, from a fresh strain origin, until the goal strain
O.cell.trsf = Matrix3.Identity
triax.goal = (-p0, -p0, -goal)
triax.stressMask = 3
triax.maxStrainRate = (200, 200, 20)
path = []
print('%8s %12s %12s %7s' % ('strain', 'p (Pa)', 'q (Pa)', 'q/p'))
stepsShear = 20000 if short else 200000
start = O.iter
while O.iter - start < stepsShear:
    O.run(100, True)
    strain = -triax.strain[2]
    p, q = stresses()
    path.append((strain, p, q))
    if len(path) % 5 == 1 or strain >= goal:
        print('%8.4f %12.1f %12.1f %7.3f' % (strain, p, q, q / p if p > 0 else float('nan')))
    if strain >= goal:
        break
if not path or not all(np.isfinite(v) for row in path for v in row):
    raise SystemExit('no stress path recorded')
if not all(p > 0 and np.isfinite(q / p) for e, p, q in path):
    raise SystemExit('the sample stopped carrying load while sheared (p <= 0 at some strain)')
if path[-1][0] < goal:
    raise SystemExit('the goal strain %.3f was not reached in %d steps (strain %.4f)' % (goal, stepsShear, path[-1][0]))
strains = [row[0] for row in path]
if len(set(strains)) != len(strains):
    raise SystemExit('the stress path repeats a state')
print('stress path: %d points from the start of shearing to strain %.4f, p %.1f Pa, q %.1f Pa, peak q/p %.3f'
      % (len(path), path[-1][0], path[-1][1], path[-1][2], max(q / p for e, p, q in path if p > 0)))
