"""What the sphere count does to a clump pair's stiffness, with YADE's own contacts (contactStiffness='spheres')
and with contactStiffness='grain'; what the option costs; what it does to a triaxial test.

1. Two fixed clumps of the bundled ellipsoid (tests/data/ellipsoid_2_1_1.stl), FrictMat young 1e8, the linear
   law; the second moved tip to tip, side to side or at 45 degrees to an overlap (0.5 to 4 % of the equivalent
   diameter) past the first touch of their spheres; the secant stiffness F / overlap for n = 5, 10, 20, 30, 70,
   and the reference: one contact of the grains, 2 E R1 R2 / (R1 + R2) = E R (R the equivalent radius).
2. The step time of a compacted periodic packing of MSS_CLUMPS (default 1000) clumps of 10 spheres (the triaxial
   test's specimen, with the option) with its pass (every 10 steps) and without, in turn on the same specimen.
3. The triaxial test (yade_mss.triaxial: 30 grains of the CT grain, dense, 100 kPa, drained to 2 %) at n = 10, 20,
   40, with and without: E50 and the peak angle.
Prints the tables and appends rows to bench/results/pair_stiffness.csv (date, commit, machine, load).
Run: yade -n -x bench/pair_stiffness.py (MSS_PARTS=1,2,3 picks the parts)."""
import csv
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.join(os.getcwd(), 'bench'))  # run from the repository root
from rows import stamp  # noqa: E402

from yade_mss import contactStiffnessEngine, generate, mssClump, mssTemplate, triaxial

HERE = os.path.dirname(os.path.abspath(sys.argv[0]))  # yade -x: __file__ is yade's own
DATA = os.path.join(HERE, '..', 'tests', 'data')
ELL = os.path.join(DATA, 'ellipsoid_2_1_1.stl')
GRAIN = os.path.join(DATA, 'grain_voxels_155x157x167.npy')
PARTS = [int(x) for x in os.environ.get('MSS_PARTS', '1,2,3').split(',')]
E = 1e8


def loop():
    return [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb()]),
            InteractionLoop([Ig2_Sphere_Sphere_ScGeom()], [Ip2_FrictMat_FrictMat_FrictPhys()],
                            [Law2_ScGeom_FrictPhys_CundallStrack()])]


RESULTS = {}


def pair(n, u, overlap, stiffness):
    O.reset()
    mat = O.materials.append(FrictMat(young=E, poisson=0.3, frictionAngle=0.5, density=2000))
    if n not in RESULTS:
        RESULTS[n] = generate(ELL, nSpheres=n)
    r = RESULTS[n]
    u = np.asarray(u, float) / np.linalg.norm(u)
    c, rad = r.centers, r.radii
    lo, hi = 0.0, 10.0
    for _ in range(100):
        m = 0.5 * (lo + hi)
        gap = (np.linalg.norm(c[:, None] - (c[None] + m * u), axis=2) - rad[:, None] - rad[None]).min()
        lo, hi = (m, hi) if gap < 0 else (lo, m)
    dv = 2 * (3 * r.targetMass.volume / (4 * np.pi)) ** (1 / 3)
    C = r.targetMass.centroid
    mssClump(r, center=tuple(C), material=mat, fixed=True, contactStiffness=stiffness)
    b, bm = mssClump(r, center=tuple(C + (hi - overlap * dv) * u), material=mat, fixed=True,
                     contactStiffness=stiffness)
    O.engines = loop() + ([contactStiffnessEngine(every=1)] if stiffness == 'grain' else []) + [
        NewtonIntegrator(damping=0)]
    O.dt = 1e-6
    for _ in range(3):
        O.step()
    F = sum(np.array(O.forces.f(i)) for i in bm)
    return abs(F.dot(u)) / (overlap * dv), sum(1 for i in O.interactions if i.isReal), E * dv / 2


def partOne(rows, base):
    print('%-10s %6s %-8s %s' % ('direction', 'overlap', 'contacts', 'K (N/m) for n = 5, 10, 20, 30, 70 '
                                 '[member pairs]; max/min over 10, 30, 70; the reference E R'))
    for name, u in (('tip', (1, 0, 0)), ('side', (0, 1, 0)), ('45 deg', (1, 1, 0))):
        for overlap in (0.005, 0.01, 0.02, 0.04):
            for stiffness in ('spheres', 'grain'):
                got = {n: pair(n, u, overlap, stiffness) for n in (5, 10, 20, 30, 70)}
                K = [got[n][0] for n in (10, 30, 70)]
                ratio = max(K) / min(K)
                print('%-10s %5.1f%% %-8s %s  max/min %.2f  ref %.3g' % (
                    name, 100 * overlap, stiffness, ' '.join('%.3g[%d]' % (got[n][0], got[n][1]) for n in got),
                    ratio, got[70][2]), flush=True)
                rows.append(dict(base, part='pair', direction=name, overlap=overlap, contactStiffness=stiffness,
                                 **{'K_n%d' % n: round(got[n][0], 1) for n in got},
                                 **{'pairs_n%d' % n: got[n][1] for n in got}, max_over_min_10_30_70=round(ratio, 3),
                                 reference=round(got[70][2], 1)))


def partTwo(rows, base):
    """What the pass costs a step: one specimen of 1,000 clumps with contactStiffness='grain', compacted for at
    most 30,000 steps (1,000 clumps take about 80,000 to 100 kPa: the contacts are there well before), the
    test's servo taken out; then blocks of 200 steps with the pass and without it (its engine dead), in turn, on
    the same specimen: the same contacts, so the ratio is the pass's cost alone (two specimens compacted
    apart are never in the same state)."""
    clumps = int(os.environ.get('MSS_CLUMPS', '1000'))
    O.reset()
    t = mssTemplate(GRAIN, nSpheres=10, voxelSize=1.25e-5)
    try:
        triaxial([t], grains=clumps, strain=0.001, records=10, seed=1, contactStiffness='grain',
                 compactionSteps=30000)
    except RuntimeError:
        pass  # not at 100 kPa yet: timed as it is
    O.engines = [e for e in O.engines if 'servoStep' not in getattr(e, 'command', '')]
    engine = [e for e in O.engines if 'contactStiffnessStep' in getattr(e, 'command', '')][0]
    O.run(500, True)
    without, with_ = [], []
    for k in range(8):
        for dead, out in ((True, without), (False, with_)):
            engine.dead = dead
            t0 = time.perf_counter()
            O.run(200, True)
            out.append((time.perf_counter() - t0) / 200)
    engine.dead = False
    plain, grain = float(np.mean(without)), float(np.mean(with_))
    contacts = O.interactions.countReal()
    print('%d clumps of 10 spheres, compacted, %d contacts: a step %.3g ms without the pass, %.3g ms with it '
          '(every %d steps): %.2fx' % (clumps, contacts, 1e3 * plain, 1e3 * grain, engine.iterPeriod,
                                      grain / plain), flush=True)
    rows.append(dict(base, part='step', clumps=clumps, step_ms_spheres=round(1e3 * plain, 3),
                     step_ms_grain=round(1e3 * grain, 3), ratio=round(grain / plain, 3)))


def partThree(rows, base):
    for n in (10, 20, 40):  # both kinds at each count in turn: a stopped run still leaves pairs to compare
        for stiffness in ('spheres', 'grain'):
            O.reset()
            t = mssTemplate(GRAIN, nSpheres=n, voxelSize=1.25e-5)
            r = triaxial([t], grains=30, strain=0.02, records=50, seed=1, contactStiffness=stiffness)
            d = r.derived
            print('triaxial %-7s n %2d: E50 %.3g Pa, phi_peak %.1f deg, e0 %.3f, %d steps' % (
                stiffness, n, d['E50_Pa'], d['phi_peak_deg'], d['e0'], r.cost['steps']), flush=True)
            save([dict(base, part='triaxial', contactStiffness=stiffness, n=n, E50_Pa=round(d['E50_Pa']),
                       phi_peak_deg=round(d['phi_peak_deg'], 2), e0=round(d['e0'], 4), steps=r.cost['steps'],
                       wall_s=round(r.cost['wall_s'], 1))])  # each test's row as it ends: the part takes hours


def main():
    base = stamp()
    for k, part in ((1, partOne), (2, partTwo), (3, partThree)):
        if k in PARTS:
            rows = []
            part(rows, base)
            save(rows)  # each part's rows as it ends


def save(rows):
    path = os.path.join(HERE, 'results', 'pair_stiffness.csv')
    fields = []
    for r in rows:
        fields += [k for k in r if k not in fields]
    old = []
    if os.path.exists(path):
        with open(path) as f:
            old = list(csv.DictReader(f))
        fields += [k for k in (old[0] if old else {}) if k not in fields]
    with open(path, 'w') as f:
        w = csv.DictWriter(f, fieldnames=fields, lineterminator='\n')
        w.writeheader()
        w.writerows(old + rows)
    print('wrote %d rows to %s' % (len(rows), path))


main()
sys.stdout.flush()
os._exit(0)
