"""What building and restoring clumps costs in YADE, against YADE's own calls on the same spheres.

Run: yade -n -x bench/yade_clumps.py [--counts 2000,20000] [--rounds 5] [--spheres 10]
Prints one table per clump count (medians over rounds that alternate ours and YADE's in the same process; the
ratios are medians of each round's) and appends one row per count to bench/results/yade_clumps.csv (date, commit,
machine, load, figures). The targets:
mssClump from a result <= 1.3x appendClumped of the same spheres (sphere bodies included); mssClumpCloud
<= 1.3x SpherePack.makeClumpCloud + toSimulation; restoreClumpProperties <= 50 us a clump. The restore's floor
is printed beside it: only the YADE calls any restore through YADE's Python API must make (each member's radius,
position and density read; a temporary shape, mass and inertia set for the sums; YADE's update; shape and mass
back; the clump's velocities), without the fingerprint checks, the loads' numbers or the records.
"""
import argparse
import csv
import datetime
import gc
import os
import sys
import time

import numpy as np

from yade import pack, utils
from yade.wrapper import FrictMat, Omega
import yade.minieigenHP as me

sys.path.insert(0, os.path.join(os.getcwd(), 'bench'))  # run from the repository root
from rows import commit, machine  # noqa: E402
from yade_mss import generate, mssClump, mssClumpCloud, mssTemplate, restoreClumpProperties

O = Omega()
HERE = os.path.join(os.getcwd(), 'bench')  # yade -x gives no __file__ of the script: run from the repository root
DATA = os.environ.get('MSS_DATA', os.path.join(HERE, '..', 'tests', 'data'))


def options():
    p = argparse.ArgumentParser(prog='yade -n -x bench/yade_clumps.py')
    p.add_argument('--counts', default='2000,20000', help='clump counts, comma-separated')
    p.add_argument('--rounds', type=int, default=5, help='alternating rounds (medians are printed)')
    p.add_argument('--spheres', type=int, default=10, help='spheres a clump')
    a = p.parse_args(sys.argv[1:])
    try:
        a.counts = [int(c) for c in a.counts.split(',')]
    except ValueError:
        p.error('--counts: integers separated by commas, got %r' % a.counts)
    if not a.counts or min(a.counts) < 1 or a.rounds < 1 or a.spheres < 1:
        p.error('--counts, --rounds and --spheres must be >= 1')
    return a


def fresh():
    O.reset()
    O.materials.append(FrictMat(density=2650, young=1e8, poisson=0.3, frictionAngle=0.5))


def places(n, pitch):
    k = int(np.ceil(n ** (1 / 3.0)))
    g = np.indices((k, k, k)).reshape(3, -1).T[:n]
    return g * pitch


def plainClumps(r, at):
    fresh()
    t = time.perf_counter()
    for c in at:
        O.bodies.appendClumped([utils.sphere(tuple(p), rad) for p, rad in zip((r.centers + c).tolist(), r.radii.tolist())],
                               discretization=0)
    return time.perf_counter() - t


def ourClumps(r, at):
    fresh()
    c0 = np.asarray(r.targetMass.centroid)
    t = time.perf_counter()
    for c in at:
        mssClump(r, center=tuple(c + c0))
    return time.perf_counter() - t


def yadeCloud(t, n, hi, seed):
    fresh()
    start = time.perf_counter()
    sp = pack.SpherePack()
    sp.makeClumpCloud(me.Vector3(0, 0, 0), me.Vector3(*hi), [t.spherePack], num=n, seed=seed)
    sp.toSimulation()
    return time.perf_counter() - start, sum(1 for b in O.bodies if b.isClump)


def ourCloud(t, n, hi, seed):
    fresh()
    start = time.perf_counter()
    made = mssClumpCloud([t], (0, 0, 0), tuple(hi), num=n, seed=seed)
    return time.perf_counter() - start, len(made)


def restores(r, at):
    """(YADE's updateClumpProperties, restoreClumpProperties) a clump, on our clumps after YADE's update."""
    ourClumps(r, at)
    t = time.perf_counter()
    O.bodies.updateClumpProperties(discretization=0)
    yade = time.perf_counter() - t
    t = time.perf_counter()
    done = restoreClumpProperties()
    ours = time.perf_counter() - t
    assert len(done) == len(at) and all(k == 'grain' for c, k in done)
    return yade, ours


def restoreFloor(r, at):
    """The Boost.Python calls a restore cannot do without, alone, on our clumps after YADE's update."""
    from yade.wrapper import Box
    ourClumps(r, at)
    O.bodies.updateClumpProperties(discretization=0)
    cids = [b.id for b in O.bodies if b is not None and b.isClump]
    tmp, V3 = Box(extents=me.Vector3(0, 0, 0)), me.Vector3
    gc.disable()  # as restoreClumpProperties does
    t = time.perf_counter()
    bodies, read = O.bodies, []
    for cid in cids:
        mem = []
        for i in sorted(bodies[cid].shape.members):
            b = bodies[i]
            sh, st = b.shape, b.state
            p = st.pos
            mem.append((b, sh, st, sh.radius, p[0], p[1], p[2], b.mat.density))
        read.append(mem)
    one = V3(1, 1, 1)
    for mem in read:
        for b, sh, st, *rest in mem:
            b.shape, st.mass, st.inertia = tmp, 1.0, one
    O.bodies.updateClumpProperties(discretization=0)
    for mem in read:
        for b, sh, st, *rest in mem:
            b.shape, st.mass = sh, 2.0
    for cid in cids:
        st = bodies[cid].state
        st.vel, st.angVel, st.angMom = V3(0, 0, 0), V3(0, 0, 0), V3(0, 0, 0)
    gc.enable()
    return time.perf_counter() - t


def main():
    a = options()
    if not os.path.isfile(os.path.join(HERE, 'yade_clumps.py')):
        sys.exit('run from the repository root: yade -n -x bench/yade_clumps.py')
    r = generate(os.path.join(DATA, 'ellipsoid_2_1_1.stl'), nSpheres=a.spheres, resolution=30)
    fresh()
    t = mssTemplate(r)
    pitch = 2 * t.boundingRadius + 0.1
    rows = []
    for n in a.counts:
        at = places(n, pitch)
        hi = np.full(3, (n * (2 * t.boundingRadius) ** 3 * 8) ** (1 / 3.0))  # a loose cloud: 1/8 filled by balls
        m = {k: [] for k in ('plain', 'ours', 'ycloud', 'ocloud', 'yupdate', 'restore', 'floor')}
        for k in range(a.rounds):
            # each pair back to back, the first of it alternating: a YADE cloud timed just before mssClump made it
            # about a fifth slower
            for yade in ((True, False) if k % 2 == 0 else (False, True)):
                m['plain' if yade else 'ours'].append((plainClumps if yade else ourClumps)(r, at))
            for yade in ((True, False) if k % 2 == 0 else (False, True)):
                tt, made = (yadeCloud if yade else ourCloud)(t, n, hi, 7 + k)
                m['ycloud' if yade else 'ocloud'].append(tt / made)
            yu, rs = restores(r, at)
            m['yupdate'].append(yu)
            m['restore'].append(rs)
            m['floor'].append(restoreFloor(r, at))
        med = {k: float(np.median(v)) for k, v in m.items()}
        # the ratios: the median of each round's (its pair timed back to back), so that a slow spell of the
        # machine between rounds does not enter them
        ratio = float(np.median([o / p for o, p in zip(m['ours'], m['plain'])]))
        cloudRatio = float(np.median([o / y for o, y in zip(m['ocloud'], m['ycloud'])]))
        load = os.getloadavg()[0]
        print('\n%d clumps of %d spheres, %d rounds, load %.2f (medians; per clump)' % (n, len(r), a.rounds, load))
        print('  appendClumped of utils.sphere bodies   %8.1f us' % (1e6 * med['plain'] / n))
        print('  mssClump from a result                 %8.1f us   %.2fx (bar 1.3x)   rounds: %s' % (
            1e6 * med['ours'] / n, ratio,
            ' '.join('%.2fx' % (o / p) for o, p in zip(m['ours'], m['plain']))))
        print('  makeClumpCloud + toSimulation          %8.1f us' % (1e6 * med['ycloud']))
        print('  mssClumpCloud                          %8.1f us   %.2fx (bar 1.3x)   rounds: %s' % (
            1e6 * med['ocloud'], cloudRatio, ' '.join('%.2fx' % (o / y) for o, y in zip(m['ocloud'], m['ycloud']))))
        print('  updateClumpProperties(discretization=0) %7.1f us' % (1e6 * med['yupdate'] / n))
        print('  restoreClumpProperties                 %8.1f us   (bar 50 us)' % (1e6 * med['restore'] / n))
        print('    its floor: the YADE calls alone      %8.1f us' % (1e6 * med['floor'] / n))
        rows.append(dict(date=datetime.datetime.now().isoformat(timespec='seconds'), commit=commit(),
                         machine=machine(), load=round(load, 2), clumps=n, spheres=len(r), rounds=a.rounds,
                         appendClumped_us=round(1e6 * med['plain'] / n, 1), mssClump_us=round(1e6 * med['ours'] / n, 1),
                         mssClump_ratio=round(ratio, 3),
                         makeClumpCloud_us=round(1e6 * med['ycloud'], 1), mssClumpCloud_us=round(1e6 * med['ocloud'], 1),
                         cloud_ratio=round(cloudRatio, 3),
                         updateClumpProperties_us=round(1e6 * med['yupdate'] / n, 1),
                         restore_us=round(1e6 * med['restore'] / n, 1),
                         restore_floor_us=round(1e6 * med['floor'] / n, 1)))
    out = os.path.join(HERE, 'results', 'yade_clumps.csv')
    os.makedirs(os.path.dirname(out), exist_ok=True)
    old = []
    if os.path.exists(out):  # rows of earlier runs keep their figures; a column added later stays empty there
        with open(out, newline='') as f:
            old = list(csv.DictReader(f))
    fields = list(rows[0]) + [k for row in old for k in row if k not in rows[0]]
    with open(out, 'w', newline='') as f:
        w = csv.DictWriter(f, fieldnames=list(dict.fromkeys(fields)), restval='')
        w.writeheader()
        w.writerows(old + rows)
    print('\nappended to %s' % os.path.relpath(out))


main()
