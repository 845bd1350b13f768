# Single-grain crushing between two platens: a breakable MSS clump of a pebble (the ellipsoid 2:1:1, 20 mm
# long) is pressed by a platen moving down at constant speed; MssBreakage splits it when the characteristic
# stress F / d^2 reaches its Weibull strength, and the fragments (MSS clumps of the cut grain, exact mass
# properties) are loaded on and break again. Prints the force-displacement curve, each split with the mass and
# momentum before and after, and the fragments' sizes; draws the curve and the grain before and after.
# Run: yade -n -x examples/crush_grain.py        (MSS_SHORT=1 for a short run; MSS_FIGURES=DIR for pictures)
import os

import numpy as np
from yade import utils
from yade_mss import MssBreakage, breakageLog, mssClump

short = os.environ.get('MSS_SHORT') == '1'
data = os.environ.get('MSS_DATA', os.path.join('tests', 'data'))
figures = os.environ.get('MSS_FIGURES')

rock = O.materials.append(FrictMat(young=1e9, poisson=0.25, frictionAngle=0.5, density=2650, label='rock'))
# the ellipsoid's long axis (x) lies flat; 20 mm long in SI units
grain, members = mssClump(os.path.join(data, 'ellipsoid_2_1_1.stl'), nSpheres=20 if short else 40, scale=5e-3,
                          center=(0, 0, 0), breakable=True, material=rock)
low = min(O.bodies[i].state.pos[2] - O.bodies[i].shape.radius for i in members)
high = max(O.bodies[i].state.pos[2] + O.bodies[i].shape.radius for i in members)
half = 0.5 * (high - low)  # the grain's half height
t = 2e-3
bottom = O.bodies.append(utils.box((0, 0, low - t), (0.02, 0.02, t), fixed=True, material=rock))
top = O.bodies.append(utils.box((0, 0, high + t), (0.02, 0.02, t), fixed=True, material=rock))
speed = 0.05  # m/s, the top platen's
O.bodies[top].state.vel = Vector3(0, 0, -speed)

O.engines = [
    ForceResetter(),
    InsertionSortCollider([Bo1_Sphere_Aabb(), Bo1_Box_Aabb()]),
    InteractionLoop([Ig2_Sphere_Sphere_ScGeom(), Ig2_Box_Sphere_ScGeom()], [Ip2_FrictMat_FrictMat_FrictPhys()],
                    [Law2_ScGeom_FrictPhys_CundallStrack()]),
    NewtonIntegrator(damping=0.5),
    # the grains' mass and momenta just before and after the breakage engine, in the same step
    PyRunner(command='record()', iterPeriod=20),
    # strength at 10 mm: 5 MPa, Weibull modulus 3; fragments below 4 mm stay whole (single spheres)
    MssBreakage(iterPeriod=20, sigma0=5e6, d0=0.01, modulus=3.0, seed=3, minSize=4e-3, resolution=40),
    PyRunner(command='compare()', iterPeriod=20),
    # fragments have smaller spheres and lighter clumps: the stable time step falls as the grain breaks
    PyRunner(command='O.dt = 0.3 * utils.PWaveTimeStep()', iterPeriod=20),
]
O.dt = 0.3 * utils.PWaveTimeStep()


def clumps():
    return [b.id for b in O.bodies if b is not None and b.isClump]


def totals(ids):
    """Mass, centre of mass, linear momentum, angular momentum about the world origin."""
    M = sum(O.bodies[i].state.mass for i in ids)
    C = sum(O.bodies[i].state.mass * np.array(O.bodies[i].state.pos) for i in ids) / M
    P = sum(O.bodies[i].state.mass * np.array(O.bodies[i].state.vel) for i in ids)
    L = sum(np.array(O.bodies[i].state.angMom) + O.bodies[i].state.mass * np.cross(O.bodies[i].state.pos,
                                                                                   O.bodies[i].state.vel)
            for i in ids)
    return M, C, P, L


def spheres():
    return [(np.array(b.state.pos), b.shape.radius, b.clumpId) for b in O.bodies
            if b is not None and b.isClumpMember]


watch = dict(before=None, ids=None)
splits = []


def record():
    watch['ids'] = clumps()
    watch['before'] = totals(watch['ids'])


def compare():
    ids = clumps()
    if ids == watch['ids']:
        return
    (M, C, P, L), (Ma, Ca, Pa, La) = watch['before'], totals(ids)
    e = breakageLog()[-1]
    d = z0 - O.bodies[top].state.pos[2]
    splits.append(dict(e, displacement=d, massError=abs(Ma - M) / M,
                       momentumError=np.linalg.norm(Pa - P) / max(np.linalg.norm(P), 1e-300),
                       # about the origin, against the momenta's own scale (L alone is ~0 for a grain at rest)
                       angularError=np.linalg.norm(La - L) / (np.linalg.norm(L) + np.linalg.norm(P) * 2 * half)))
    print('split at %.3f mm: clump %d (%.2f mm) -> %s mm, %s spheres; sigma %.3g MPa >= strength %.3g MPa; '
          'mass %.1e, P %.1e, L %.1e relative change' % (
              d * 1e3, e['parent'], np.cbrt(6 * e['parentVolume'] / np.pi) * 1e3,
              ', '.join('%.2f' % (s * 1e3) for s in e['sizes']), e['spheres'], e['sigma'] / 1e6,
              e['strength'] / 1e6, splits[-1]['massError'], splits[-1]['momentumError'], splits[-1]['angularError']))


def point():
    """A point of the force-displacement curve; stops the run when done."""
    d = z0 - O.bodies[top].state.pos[2]
    curve.append((d, abs(O.forces.f(top)[2])))
    if (short and splits and d > splits[0]['displacement'] + 0.05e-3) or d > (0.3 if short else 0.5) * 2 * half:
        O.pause()


before = spheres()
mass0 = totals([grain])[0]
curve = []  # (platen displacement, force on the top platen)
z0 = O.bodies[top].state.pos[2]
O.engines = O.engines + [PyRunner(command='point()', iterPeriod=20)]
O.run()
O.wait()

ids = clumps()
print('fragments    %d, sizes %s mm' % (len(ids), ', '.join(
    '%.2f' % (np.cbrt(6 * O.bodies[i].state.mass / 2650 / np.pi) * 1e3) for i in sorted(ids))))
print('mass         before %.6e kg, after %.6e kg (relative change %.1e)' % (
    mass0, sum(O.bodies[i].state.mass for i in ids), abs(sum(O.bodies[i].state.mass for i in ids) - mass0) / mass0))
peak = max(f for d, f in curve)
print('peak force   %.1f N at %.3f mm; splits %d' % (peak, 1e3 * max(curve, key=lambda x: x[1])[0], len(splits)))

if figures:
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    from matplotlib.collections import PatchCollection
    from matplotlib.patches import Circle
    os.makedirs(figures, exist_ok=True)
    fig, ax = plt.subplots(figsize=(6, 4))
    c = np.array(curve)
    ax.plot(c[:, 0] * 1e3, c[:, 1], lw=1)
    for s in splits:
        ax.axvline(s['displacement'] * 1e3, color='C3', lw=0.6, ls='--')
    ax.set_xlabel('platen displacement (mm)')
    ax.set_ylabel('force on the top platen (N)')
    ax.set_title('Crushing one pebble: %d split%s (dashed)' % (len(splits), '' if len(splits) == 1 else 's'))
    fig.tight_layout()
    fig.savefig(os.path.join(figures, 'crush_force.png'), dpi=120)
    fig, axes = plt.subplots(1, 2, figsize=(9, 3.4), sharey=True)
    # the fragments between the platens (the others were thrown out by the energy each split releases)
    now = [(p, r, k) for p, r, k in spheres() if abs(p[0]) < 0.015 and abs(p[1]) < 0.015 and low - 1e-3 < p[2] < high]
    shown = len(set(k for p, r, k in now))
    for ax, ss, title in ((axes[0], before, 'before'),
                          (axes[1], now, 'after: %d fragments, %d still between the platens' % (len(ids), shown))):
        owners = sorted(set(k for p, r, k in ss))
        colours = {k: plt.cm.tab20(i % 20) for i, k in enumerate(owners)}
        ax.add_collection(PatchCollection([Circle((p[0] * 1e3, p[2] * 1e3), r * 1e3) for p, r, k in ss],
                                          facecolors=[colours[k] for p, r, k in ss], alpha=0.5, edgecolors='k',
                                          linewidths=0.3))
        for z in (low, O.bodies[top].state.pos[2] - t) if ss is now else (low, high):  # the platens
            ax.axhline(z * 1e3, color='0.3', lw=1.5)
        ax.set_aspect('equal')
        ax.set_xlim(-15, 15)
        ax.set_ylim(1e3 * low - 1, 1e3 * high + 1)
        ax.set_xlabel('x (mm)')
        ax.set_title(title)
    axes[0].set_ylabel('z (mm)')
    fig.suptitle('Spheres seen along y, a colour per clump; grey lines: the platens')
    fig.tight_layout()
    fig.savefig(os.path.join(figures, 'crush_grain.png'), dpi=120)

# checks that can fail: the grain carried load, broke, and each split kept mass and momenta
assert peak > 10.0, 'the grain never carried load (peak force %g N)' % peak
assert splits, 'the grain never broke'
assert all(s['sigma'] >= s['strength'] for s in splits)
assert all(s['massError'] < 1e-12 for s in splits), [s['massError'] for s in splits]
assert all(s['momentumError'] < 1e-10 for s in splits), [s['momentumError'] for s in splits]
assert all(s['angularError'] < 1e-10 for s in splits), [s['angularError'] for s in splits]
assert abs(sum(O.bodies[i].state.mass for i in ids) - mass0) < 1e-12 * mass0
after = [f for d, f in curve if d > splits[0]['displacement']]
assert min(after[:5]) < 0.9 * max(f for d, f in curve if d <= splits[0]['displacement']), 'no force drop at the split'
print('crush_grain: checks passed')
