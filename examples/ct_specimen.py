# A labelled CT volume to a DEM assembly, then compressed: every grain of the specimen becomes a clump at its
# true position with its exact mass properties (mssAssembly; the same as `mss batch` then mssAssembly(OUTDIR)),
# inside a box whose lid then moves down until the loose specimen jams (it carries five times its weight between
# lid and floor). Prints the assembly's figures, the lid's force against its travel and the force it holds.
# Run: yade -n -x examples/ct_specimen.py       (MSS_SHORT=1 for a short run; MSS_FIGURES=DIR for a picture)
# Environment: MSS_SPECIMEN  a labelled volume (.npy or .tif, 0 is background; voxel edge MSS_VOXEL_SIZE, m);
#              by default a synthetic specimen of 40 irregular grains (yade_mss.syntheticSpecimen).
import os
import time

import numpy as np
from yade import utils
from yade_mss import mssAssembly, regions, syntheticSpecimen

short = os.environ.get('MSS_SHORT') == '1'
h = float(os.environ.get('MSS_VOXEL_SIZE', '2e-5'))  # 20 micrometre voxels: grains of about 0.4 mm
source = os.environ.get('MSS_SPECIMEN') or syntheticSpecimen((100, 100, 100) if short else (160, 160, 160),
                                                             20 if short else 40, seed=3)
labels = np.load(source) if isinstance(source, str) and source.endswith('.npy') else source
sand = O.materials.append(FrictMat(young=5e7, poisson=0.3, frictionAngle=0.5, density=2650, label='sand'))
t0 = time.perf_counter()
clumps = mssAssembly(source, voxelSize=h, nSpheres=12, minVoxels=100, material=sand)
print('assembly     %d grains as clumps (%d spheres) in %.2f s' % (len(clumps), sum(len(m) for c, m in clumps.values()),
                                                                     time.perf_counter() - t0))
# the grains' exact volumes against their voxel counts: the clumps carry the grains' own mass
counts = {r.label: r.voxels for r in regions(labels)}
err = max(abs(O.bodies[c].state.mass / (2650 * counts[k] * h ** 3) - 1) for k, (c, m) in clumps.items())
print('mass         largest error against the voxel counts %.1e' % err)
if err > 1e-9:
    raise SystemExit('a clump does not carry its grain\'s mass')

# a box around the specimen, its lid moving down at constant speed
lo = np.array([min(O.bodies[i].state.pos[a] - O.bodies[i].shape.radius for c, m in clumps.values() for i in m)
               for a in range(3)])
hi = np.array([max(O.bodies[i].state.pos[a] + O.bodies[i].shape.radius for c, m in clumps.values() for i in m)
               for a in range(3)])
walls = [O.bodies.append(utils.wall(lo[a], axis=a, sense=1, material=sand)) for a in range(3)]
walls += [O.bodies.append(utils.wall(hi[a], axis=a, sense=-1, material=sand)) for a in range(2)]
lid = O.bodies.append(utils.wall(hi[2], axis=2, sense=-1, material=sand))
O.engines = [
    ForceResetter(),
    InsertionSortCollider([Bo1_Sphere_Aabb(), Bo1_Wall_Aabb()]),
    InteractionLoop([Ig2_Sphere_Sphere_ScGeom(), Ig2_Wall_Sphere_ScGeom()], [Ip2_FrictMat_FrictMat_FrictPhys()],
                    [Law2_ScGeom_FrictPhys_CundallStrack()]),
    NewtonIntegrator(damping=0.4, gravity=(0, 0, -9.81)),
]
step, setBy = clumps.timeStep()  # PWaveTimeStep, and which grains' smallest spheres set it
print('time step    %.3g s, set by grain%s %s' % (step, 's' if len(setBy) > 1 else '', ', '.join(map(str, setBy[:5]))))
O.dt = 0.5 * step
O.step()
kept, of = clumps.contactsKept()  # the scan's contacts that are interactions in YADE after one step
print('contacts     %d of the scan\'s %d interact in YADE' % (kept, of))
height = hi[2] - lo[2]
weight = 9.81 * sum(O.bodies[c].state.mass for c, m in clumps.values())
# the lid moves down at constant speed (half the height in 4000 steps); where it carries five times the
# specimen's weight it stops for 1000 steps: the specimen has jammed when the lid then still carries the weight
# (squeezed between lid and floor), else the lid goes on (it had only struck a grain in the air)
speed = 0.5 * height / (4000 * O.dt)
O.bodies[lid].state.blockedDOFs = 'xyzXYZ'
print('%10s %12s %12s' % ('travel', 'lid force', 'held'))
jammed, held, path = False, 0.0, []
while not jammed and hi[2] - O.bodies[lid].state.pos[2] < 0.95 * height:
    O.bodies[lid].state.vel = (0, 0, -speed)
    O.run(50, True)
    force = abs(O.forces.f(lid, True)[2])
    path.append((hi[2] - O.bodies[lid].state.pos[2], force))
    if force >= 5 * weight:
        O.bodies[lid].state.vel = (0, 0, 0)
        O.run(1000, True)
        held = abs(O.forces.f(lid, True)[2])
        jammed = held >= weight
        print('%10.3e %12.4e %12.4e' % (hi[2] - O.bodies[lid].state.pos[2], force, held))
travel = hi[2] - O.bodies[lid].state.pos[2]
if not jammed:
    raise SystemExit('the lid travelled %.3g of the specimen\'s %.3g height without holding its weight (%.3g N): '
                     'the specimen never jammed' % (travel, height, weight))
print('jammed       at travel %.4g (%.0f%% of the height): the still lid holds %.4g N, %.1f times the weight'
      % (travel, 100 * travel / height, held, held / weight))
if not all(np.isfinite(O.bodies[c].state.pos).all() for c, m in clumps.values()):
    raise SystemExit('a clump left the box')
if os.environ.get('MSS_FIGURES'):  # the jammed specimen from the side, and the lid's force against its travel
    from yade_mss.pictures import sideView
    ids = [(c, i) for c, m in clumps.values() for i in m]

    def lidCurve(ax):
        ax.plot([1e3 * t for t, f in path], [f / weight for t, f in path], lw=0.8)
        ax.set_xlabel('lid travel (mm)')
        ax.set_ylabel('lid force / the specimen\'s weight')
        ax.set_title('the lid moving down until the specimen jams')
    sideView([tuple(O.bodies[i].state.pos) for c, i in ids], [O.bodies[i].shape.radius for c, i in ids],
             [c for c, i in ids], os.path.join(os.environ['MSS_FIGURES'], 'ct_specimen.png'),
             'a CT specimen as clumps (mssAssembly), jammed under the lid', extra=lidCurve)
