"""What a triaxial test of our clumps costs (yade_mss.studies.triaxial): for each (clumps, spheres) of MSS_CASES
(default 200x10, 200x20, 1000x10, 1000x20) the bundled CT grain (2 mm) is compacted to 100 kPa (dense) and
sheared drained; then, on the sheared specimen, the step time of the test (its servo included), of our clumps
alone (the servo's PyRunner taken out, as in each comparison below), of YADE's own clumps of the same spheres at the same places (O.bodies.appendClumped), and of as many
plain YADE spheres of the members' radii compacted to the same pressure by the same servo. Prints the steps and
the wall time to 20 % axial strain (the steps the strain rate needs there times the measured step time, plus the
compaction's measured wall time), and appends a row a case to bench/results/triaxial.csv (date, commit, machine,
load). Run on a quiet machine: yade -n -x bench/triaxial.py (MSS_CASES=200x10 for one case)."""
import csv
import math
import os
import sys
import time

import numpy as np

from yade import pack, utils

sys.path.insert(0, os.path.join(os.getcwd(), 'bench'))  # run from the repository root
from rows import stamp  # noqa: E402

from yade_mss import MssResult, mssClump, mssTemplate
from yade_mss.studies import triaxial
import yade_mss.studies._triaxial as engine  # the test's own engines and servo, for the plain spheres

HERE = os.path.dirname(os.path.abspath(sys.argv[0]))  # yade -x: __file__ is yade's own
GRAIN = os.path.join(HERE, '..', 'tests', 'data', 'grain_voxels_155x157x167.npy')
CASES = [tuple(int(x) for x in c.split('x')) for c in os.environ.get('MSS_CASES', '200x10,200x20,1000x10,1000x20')
         .split(',')]
TIMED = int(os.environ.get('MSS_TIMED_STEPS', '2000'))
P0 = 1e5


def timed(steps):
    O.run(200, True)  # warm: new contacts, the collider's sort
    t = time.perf_counter()
    O.run(steps, True)
    return (time.perf_counter() - t) / steps


def members():
    """Every clump's member spheres: [(centres (k, 3), radii (k,))]."""
    out = []
    for b in O.bodies:
        if b is not None and b.isClump:
            ids = list(b.shape.members.keys())
            out.append((np.array([[O.bodies[i].state.pos[j] for j in range(3)] for i in ids]),
                        np.array([O.bodies[i].shape.radius for i in ids])))
    return out


def freshScene(cell, mat, dt):
    """A new scene with the sheared specimen's cell, material, engines (no servo) and time step: each kind of
    body is timed in a scene of its own (a scene whose bodies were erased and appended again keeps the holes in
    its body container, and a step walks them: the kind timed later paid for them)."""
    O.reset()
    O.periodic = True
    O.cell.hSize = cell
    m = O.materials.append(FrictMat(young=mat.young, poisson=mat.poisson, frictionAngle=mat.frictionAngle,
                                    density=mat.density))
    O.engines = engine._engines(dict(damping=0.2))
    O.dt = dt
    return m


def yadeClumps(groups, cell, mat, dt):
    """YADE's own clumps of the same spheres at the same places, in a scene of their own."""
    m = freshScene(cell, mat, dt)
    for c, r in groups:
        O.bodies.appendClumped([utils.sphere(tuple(p), float(x), material=m) for p, x in zip(c, r)])


def ourClumps(groups, cell, mat, dt):
    """Ours (mssClump) of the same spheres at the same places, built as YADE's were (mass: the union's; the
    step's cost does not depend on the masses)."""
    m = freshScene(cell, mat, dt)
    for c, r in groups:
        mssClump(MssResult(c, r), mass='union', material=m)


def plainSpheres(radii, mat, dt):
    """As many free spheres of these radii, in a loose periodic cloud, compacted to P0 by the test's servo."""
    O.reset()
    O.periodic = True
    solid = float(np.sum(4 / 3 * math.pi * radii ** 3))
    L = (solid / 0.25) ** (1 / 3)
    O.cell.setBox(L, L, L)
    O.materials.append(mat)
    sp = pack.SpherePack()
    sp.makeCloud((0, 0, 0), (L, L, L), rMean=float(np.mean(radii)), rRelFuzz=float(np.std(radii) / np.mean(radii)),
                 num=len(radii), periodic=True, seed=1)
    sp.toSimulation(material=mat)
    O.engines = engine._engines(dict(damping=0.2))
    O.dt = dt
    engine.SERVO.set((P0,) * 3, (5e-5 / dt,) * 3)
    for _ in range(200):
        O.run(500, True)
        p = float(np.trace(engine._stress(utils)) / 3)
        if abs(p / P0 - 1) < 0.02 and utils.unbalancedForce() < 0.05:
            break
    return len(sp), p


def case(N, n):
    O.reset()
    t = mssTemplate(GRAIN, nSpheres=n, voxelSize=1.25e-5)
    w0 = time.perf_counter()
    r = triaxial([t], grains=N, strain=0.002, records=10, confining=P0, seed=1)
    setup = time.perf_counter() - w0
    shear = r.records[-1]['axial_strain'] / r.cost['shear_steps']  # strain a step
    steps20 = 0.2 / shear
    mat = O.materials[0]
    withServo = timed(TIMED)  # the test's step: its servo included
    servo = [e for e in O.engines if type(e).__name__ == 'PyRunner']
    O.engines = [e for e in O.engines if e not in servo]  # the clumps' own cost, as YADE's below
    ours = timed(TIMED)
    groups = members()
    spheres = sum(len(g[1]) for g in groups)
    cell, dt = O.cell.hSize, O.dt
    yadeClumps(groups, cell, mat, dt)
    theirs = timed(TIMED)
    ourClumps(groups, cell, mat, dt)
    fresh = timed(TIMED)
    radii = np.concatenate([g[1] for g in groups])
    count, p = plainSpheres(radii, mat, dt)
    O.engines = [e for e in O.engines if type(e).__name__ != 'PyRunner']
    plain = timed(TIMED)
    return dict(clumps=N, spheres_per_clump=n, spheres=spheres, dt_s=dt, compaction_steps=r.compaction['steps'],
                setup_s=round(setup, 2), steps_to_20pct=int(round(r.compaction['steps'] + steps20)),
                test_step_ms=round(1e3 * withServo, 3), step_ms=round(1e3 * ours, 3),
                fresh_step_ms=round(1e3 * fresh, 3),
                yade_clumps_step_ms=round(1e3 * theirs, 3),
                plain_spheres_step_ms=round(1e3 * plain, 3), plain_p_Pa=round(p),
                wall_to_20pct_s=round(setup + steps20 * withServo, 1), ratio_yade_clumps=round(fresh / theirs, 3),
                ratio_plain=round(ours / plain, 3))


def main():
    rows = []
    path = os.path.join(HERE, 'results', 'triaxial.csv')
    for N, n in CASES:
        figures = case(N, n)
        row = stamp()  # after the case: its load is the last minute's of the case, not of the bench's start
        row.update(figures)
        rows.append(row)
        new = not os.path.exists(path)
        with open(path, 'a') as f:  # a row as each case ends: a long run stopped keeps what it measured
            w = csv.DictWriter(f, fieldnames=list(row), lineterminator='\n')
            if new:
                w.writeheader()
            w.writerow(row)
        print('%5d clumps x %2d spheres: dt %.3g s, %d steps to 20 %% (%d compacting), the test\'s step %.3g ms; '
              'without its servo %.3g ms, built afresh %.3g ms (YADE\'s clumps %.3g ms: %.2fx; plain spheres %.3g ms: '
              '%.2fx), wall to 20 %% %.0f s' % (N, n, row['dt_s'], row['steps_to_20pct'], row['compaction_steps'],
                                                row['test_step_ms'], row['step_ms'], row['fresh_step_ms'],
                  row['yade_clumps_step_ms'], row['ratio_yade_clumps'], row['plain_spheres_step_ms'],
                  row['ratio_plain'], row['wall_to_20pct_s']), flush=True)
    print('appended %d rows to %s' % (len(rows), path))


main()
sys.stdout.flush()
os._exit(0)
