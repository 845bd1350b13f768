# yade-mss quick start: a CT-scanned femur to one clump of 70 spheres, dropped on a plane.
# Run: yade -n -x examples/quickstart.py        (MSS_SHORT=1 for a short run; MSS_FIGURES=DIR for a picture)
import os

import numpy as np
from yade import utils
from yade_mss import generate, mssClump, score

femur = os.environ.get('MSS_FEMUR', os.path.join('tests', 'data', 'human_femur.stl'))
short = os.environ.get('MSS_SHORT') == '1'

# SI units (m, kg, s). The femur's mesh is in millimetres: scale=1e-3 makes metres of it as it is read.
# The grain: 70 spheres on the paper's grid (103 voxels along the shortest edge, 128 x 107 x 206).
result = generate(femur, nSpheres=70, resolution=103, scale=1e-3)
s = score(femur, result, scale=1e-3)  # an independent grid, offset from the generation grid

# a soft bone-like material (Young's modulus 1 MPa): large time steps for a quick drop
bone = O.materials.append(FrictMat(density=1900, young=1e6, poisson=0.3, frictionAngle=0.5, label='bone'))
ground = O.bodies.append(utils.wall(0, axis=2, sense=1, material=bone))
# the clump with the femur's exact mass, centre of mass and inertia tensor, lifted 20 mm above the ground
zmin = (result.centers[:, 2] - result.radii).min()
cid, members = mssClump(result, material=bone, center=result.targetMass.centroid + (0, 0, 0.02 - zmin))
st = O.bodies[cid].state

print('spheres      %d' % len(members))
print('dice         %.4f (generation grid)  %.4f (independent grid)' % (result.metrics['dice'], s['dice']))
print('mass         %.6g kg  (femur volume %.6g m^3)' % (st.mass, result.targetMass.volume))
print('inertia      %.6g %.6g %.6g kg m^2 (principal)' % tuple(st.inertia))
print('generated in %.3f s' % result.metrics['secondsTotal'])

O.engines = [
    ForceResetter(),
    InsertionSortCollider([Bo1_Sphere_Aabb(), Bo1_Wall_Aabb()]),
    InteractionLoop([Ig2_Sphere_Sphere_ScGeom(), Ig2_Wall_Sphere_ScGeom()], [Ip2_FrictMat_FrictMat_FrictPhys()],
                    [Law2_ScGeom_FrictPhys_CundallStrack()]),
    NewtonIntegrator(damping=0.4, gravity=(0, 0, -9.81)),
]
O.dt = 0.5 * utils.PWaveTimeStep()
steps = 3000 if short else 30000
O.run(steps, True)
v = np.linalg.norm(np.array(st.vel))
print('after %d steps (%.3f s): height of centre %.3f mm, speed %.3g mm/s, %d contacts with the ground'
      % (steps, O.time, 1e3 * st.pos[2], 1e3 * v, len([i for i in O.bodies[ground].intrs() if i.isReal])))
if not short and v > 1e-3:
    raise SystemExit('the femur did not come to rest')
if os.environ.get('MSS_FIGURES'):  # the clump against the femur: three views and a section
    result.preview(os.path.join(os.environ['MSS_FIGURES'], 'quickstart_femur.png'), grain=femur, scale=1e-3)
