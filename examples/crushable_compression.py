# One-dimensional compression of crushable grains: a periodic packing of breakable MSS clumps (pebbles, the
# ellipsoid 2:1:1, sizes 1.6-3.2 mm) compacted isotropically, then compressed along z with no lateral strain
# (oedometric) up to a vertical stress where grains break. MssBreakage splits every grain whose characteristic
# stress F / d^2 reaches its Weibull strength (size effect: smaller grains are stronger); fragments break again.
# Prints the grading before and after and Hardin's relative breakage B_r; draws the grading curves and the
# stress-strain path.
# Run: yade -n -x examples/crushable_compression.py     (MSS_SHORT=1 for a short run; MSS_FIGURES=DIR for pictures)
import os

import numpy as np
from yade import utils
from yade_mss import MssBreakage, breakageLog, grainSizes, mssClumpCloud, mssTemplate, relativeBreakage

short = os.environ.get('MSS_SHORT') == '1'
data = os.environ.get('MSS_DATA', os.path.join('tests', 'data'))
figures = os.environ.get('MSS_FIGURES')

rock = O.materials.append(FrictMat(young=5e9, poisson=0.25, frictionAngle=0.5, density=2650, label='rock'))
pebble = mssTemplate(os.path.join(data, 'ellipsoid_2_1_1.stl'), nSpheres=10, resolution=40)
n = 100 if short else 250
L = 0.021 if short else 0.029
O.periodic = True
O.cell.hSize = Matrix3(L, 0, 0, 0, L, 0, 0, 0, L)
clumps = mssClumpCloud(pebble, (0, 0, 0), (L, L, L), num=n, periodic=True, seed=2, psdSizes=[1.6e-3, 3.2e-3],
                       psdCumm=[0, 1], breakable=True, material=rock)
print('packing      %d breakable clumps, %d spheres, cell %.1f mm' % (len(clumps), sum(len(m) for c, m in clumps),
                                                                     L * 1e3))
before = grainSizes()
cutoff = 0.8e-3  # the grading's lower bound for B_r: pieces below it are dust (single spheres, never break)

p0 = 0.2e6
sigmaMax = 6e6 if short else 12e6
O.engines = [
    ForceResetter(),
    InsertionSortCollider([Bo1_Sphere_Aabb()]),
    InteractionLoop([Ig2_Sphere_Sphere_ScGeom()], [Ip2_FrictMat_FrictMat_FrictPhys()],
                    [Law2_ScGeom_FrictPhys_CundallStrack()]),
    PeriTriaxController(label='triax', goal=(-p0, -p0, -p0), stressMask=7, dynCell=True, maxStrainRate=(500, 500, 500),
                        maxUnbalanced=0.1, relStressTol=0.05, doneHook='compacted()'),
    NewtonIntegrator(damping=0.4),
    PyRunner(command='record()', iterPeriod=50),
]
O.dt = 0.5 * utils.PWaveTimeStep()
path = []  # (axial strain, vertical stress)
state = dict(phase='isotropic', z0=None)


def compacted():
    """Isotropic compaction done: breakage on, compression along z at no lateral strain."""
    state['phase'], state['z0'] = 'oedometric', O.cell.hSize[2, 2]
    ex, ey = triax.strain[0], triax.strain[1]  # strains count from the first cell: keep these (no lateral strain)
    O.engines = O.engines[:3] + [
        PeriTriaxController(label='triax', goal=(ex, ey, -sigmaMax), stressMask=4, dynCell=True,
                            maxStrainRate=(20, 20, 20), maxUnbalanced=0.05, relStressTol=0.02, doneHook='done()'),
        NewtonIntegrator(damping=0.4),
        MssBreakage(iterPeriod=100, sigma0=6e6, d0=2e-3, modulus=3.0, seed=5, minSize=cutoff, resolution=30),
        PyRunner(command='record()', iterPeriod=50)]
    print('compacted    p %.0f kPa, porosity %.3f, %d steps' % (-sum(triax.stress) / 3e3, porosity(), O.iter))


def done():
    O.pause()


def porosity():
    solid = sum(O.bodies[c].state.mass for c in clumpIds()) / O.materials[rock].density
    return 1 - solid / O.cell.volume


def clumpIds():
    return [b.id for b in O.bodies if b is not None and b.isClump]


def record():
    if state['phase'] == 'oedometric':
        s = utils.getStress()
        path.append((1 - O.cell.hSize[2, 2] / state['z0'], -s[2, 2], -s[0, 0]))


O.run()
O.wait()
after = grainSizes()
log = breakageLog()
Br = relativeBreakage(before, after, cutoff)
e, sz, sx = path[-1]
print('compressed   vertical stress %.2f MPa, lateral %.2f MPa (K0 %.2f), axial strain %.3f, porosity %.3f'
      % (sz / 1e6, sx / 1e6, sx / sz, e, porosity()))
print('breakage     %d splits, %d grains -> %d clumps; Hardin B_r = %.3f (cut-off %.1f mm)'
      % (len(log), len(before[0]), len(after[0]), Br, cutoff * 1e3))
for name, (d, m) in (('before', before), ('after', after)):
    q = np.percentile(d, [10, 50, 90]) * 1e3
    print('grading      %-6s d10 %.2f  d50 %.2f  d90 %.2f mm (by number), mass %.6e kg' % (name, q[0], q[1], q[2], m.sum()))

if figures:
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    os.makedirs(figures, exist_ok=True)
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(10, 4))
    for name, (d, m), c in (('before', before, 'C0'), ('after (%d splits)' % len(log), after, 'C3')):
        k = np.argsort(d)
        a1.semilogx(np.concatenate([[d[k][0]], d[k]]) * 1e3, np.concatenate([[0], np.cumsum(m[k]) / m.sum()]) * 100,
                    drawstyle='steps-post', color=c, label=name)
    a1.axvline(cutoff * 1e3, color='0.5', ls=':', label='cut-off (B_r)')
    a1.set_xlabel('size: diameter of the sphere of the grain volume (mm)')
    a1.set_ylabel('mass finer (%)')
    a1.set_title('Grading, Hardin B_r = %.3f' % Br)
    a1.legend(loc='upper left')
    p = np.array(path)
    a2.plot(p[:, 0], p[:, 1] / 1e6, label='vertical')
    a2.plot(p[:, 0], p[:, 2] / 1e6, label='lateral')
    t = [x['iter'] for x in log]
    a2.set_xlabel('axial strain')
    a2.set_ylabel('stress (MPa)')
    a2.set_title('Oedometric compression of %d grains' % len(before[0]))
    a2.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(figures, 'crushable_compression.png'), dpi=120)

# checks that can fail: the sample carried the stress asked for, grains broke, the mass stayed
assert state['phase'] == 'oedometric', 'the isotropic compaction never finished'
assert abs(sz - sigmaMax) < 0.05 * sigmaMax, 'vertical stress %.3g, not %.3g' % (sz, sigmaMax)
assert np.isfinite(sx) and sx > 0, 'no lateral stress'
assert log, 'no grain broke'
assert Br > 0, 'no breakage by Hardin'
assert abs(after[1].sum() - before[1].sum()) < 1e-12 * before[1].sum(), 'mass changed'
assert len(after[0]) > len(before[0])
print('crushable_compression: checks passed')
