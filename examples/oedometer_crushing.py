# One-dimensional compression of crushable grains (an oedometer): breakable MSS clumps of two grain shapes
# (the ellipsoid 2:1:1 and an octahedron, 1.6-3.2 mm, uniform by mass) in a rigid box, so no lateral strain;
# the lid moves down at constant speed and MssBreakage splits each grain whose characteristic stress F / d^2
# reaches its Weibull strength. Prints the stress-strain path, each split, and the grading before and after
# with Hardin's relative breakage B_r; draws the grading curves, the stress path and a section of the sample.
# Run: yade -n -x examples/oedometer_crushing.py     (MSS_SHORT=1 for a short run; MSS_FIGURES=DIR for pictures)
import os
import time

import numpy as np
from yade import utils
from yade_mss import MssBreakage, breakageLog, grainSizes, mssClumpCloud, mssTemplate, relativeBreakage

short = os.environ.get('MSS_SHORT') == '1'
data = os.environ.get('MSS_DATA', os.path.join('tests', 'data'))
figures = os.environ.get('MSS_FIGURES')
started = time.time()

rock = O.materials.append(FrictMat(young=2e10, poisson=0.25, frictionAngle=0.5, density=2650, label='rock'))
smooth = O.materials.append(FrictMat(young=2e10, poisson=0.25, frictionAngle=0.0, density=2650, label='walls'))
templates = [mssTemplate(os.path.join(data, name), nSpheres=12) for name in ('ellipsoid_2_1_1.stl', 'octahedron.stl')]
n = 40 if short else 150
W = 0.010 if short else 0.014  # the box's width (x and y)
H0 = 0.030 if short else 0.060  # the loose cloud's height (grains placed where their bounding balls are free)
clumps = mssClumpCloud(templates, (0, 0, 0), (W, W, H0), num=n, seed=5, psdSizes=[1.6e-3, 3.2e-3],
                       psdCumm=[0.0, 1.0], distributeMass=True, breakable=True, material=rock)
print('packing      %d clumps, %d spheres, box %.0f x %.0f mm' % (len(clumps), sum(len(m) for c, m in clumps),
                                                                W * 1e3, W * 1e3))
t = 2e-3  # wall thickness
for c, e in (((-t, W / 2, H0), (t, W, H0)), ((W + t, W / 2, H0), (t, W, H0)), ((W / 2, -t, H0), (W, t, H0)),
             ((W / 2, W + t, H0), (W, t, H0)), ((W / 2, W / 2, -t), (W, W, t))):
    O.bodies.append(utils.box(c, e, fixed=True, material=smooth))
lid = O.bodies.append(utils.box((W / 2, W / 2, 2 * H0), (W, W, t), fixed=True, material=smooth))

O.engines = [
    ForceResetter(),
    InsertionSortCollider([Bo1_Sphere_Aabb(), Bo1_Box_Aabb()]),
    # Hertz-Mindlin contacts with viscous damping (restitution 0.3): a split releases the elastic energy its
    # grain's contacts stored, and the fragments' collisions must lose it as real ones do
    InteractionLoop([Ig2_Sphere_Sphere_ScGeom(), Ig2_Box_Sphere_ScGeom()],
                    [Ip2_FrictMat_FrictMat_MindlinPhys(en=0.3, es=0.3)], [Law2_ScGeom_MindlinPhys_Mindlin()]),
    NewtonIntegrator(damping=0.4, gravity=(0, 0, -2e4), label='newton'),
    # strength 10 MPa at 2 mm, Weibull modulus 3; pieces below 1 mm are single spheres that do not break
    MssBreakage(iterPeriod=200, sigma0=10e6, d0=2e-3, modulus=3.0, seed=1, minSize=1.0e-3, resolution=40,
                nSpheres=6, rMin=0.15e-3, label='breakage'),
    PyRunner(command='watch()', iterPeriod=200, label='watching'),
]
# fragments have smaller spheres: watch() sets the step again as the grains break
O.dt = 0.6 * utils.PWaveTimeStep()
area = W * W
p0, speed = 0.2e6, 0.05  # the preload (Pa) and the lid's speed (m/s): a strain rate of about 5/s
goal, sigmaMax = (0.08, 25e6) if short else (0.2, 25e6)  # the run ends at this strain or this stress
state = dict(phase=0, H=None, seen=0)
path = []  # (strain, vertical stress on the lid, splits so far, real contacts)


def height():
    return O.bodies[lid].state.pos[2] - t


def stress():
    return abs(O.forces.f(lid)[2]) / area


def spheres():
    return [(np.array(b.state.pos), b.shape.radius, b.clumpId) for b in O.bodies
            if b is not None and b.isClumpMember]


def watch():
    O.dt = 0.6 * utils.PWaveTimeStep()
    if state['phase'] == 0:
        # fast down to the first contacts, then at the loading speed
        O.bodies[lid].state.vel = Vector3(0, 0, -(speed if stress() > 0.1 * p0 else 10 * speed))
        if stress() > p0:
            state.update(phase=1, H=height(), before=grainSizes(), section=spheres())
            breakage.dead = False
            print('preloaded    %.0f kPa at height %.2f mm, iteration %d' % (stress() / 1e3, height() * 1e3, O.iter))
        return
    e = 1 - height() / state['H']
    log = breakageLog()
    for ev in log[state['seen']:]:
        print('split        strain %.4f: grain %d (%.2f mm) -> %s mm, sigma %.2f MPa >= strength %.2f MPa' % (
            e, ev['parent'], np.cbrt(6 * ev['parentVolume'] / np.pi) * 1e3,
            ' + '.join('%.2f' % (s * 1e3) for s in ev['sizes']), ev['sigma'] / 1e6, ev['strength'] / 1e6))
    state['seen'] = len(log)
    path.append((e, stress(), len(log), len([i for i in O.interactions if i.isReal])))
    if len(path) % 50 == 0:
        print('strain %.4f  stress %6.2f MPa  splits %4d  contacts %5d  dt %.2e  %4.0f s' % (
            e, stress() / 1e6, len(log), path[-1][3], O.dt, time.time() - started))
    if e > goal or stress() > sigmaMax:
        O.pause()


# 1. the grains settle under a strong gravity (quick) until nearly at rest
watching.dead = breakage.dead = True
for k in range(80):
    O.run(1000, True)
    if k > 20 and utils.unbalancedForce() < 0.05:
        break
top = max(b.state.pos[2] + b.shape.radius for b in O.bodies if b.isClumpMember)
print('settled      iteration %d, unbalanced force %.3f, heap %.2f mm high' % (O.iter, utils.unbalancedForce(),
                                                                             top * 1e3))
# 2. no gravity (the stresses are thousands of times the grains' weight); the lid comes down to the preload,
# then the breakage engine starts and the lid goes on at the loading speed
newton.gravity = Vector3(0, 0, 0)
O.bodies[lid].state.pos = Vector3(W / 2, W / 2, top + t)
watching.dead = False
mass0 = sum(O.bodies[c].state.mass for c, m in clumps)
O.run()
O.wait()

before, after = state['before'], grainSizes()
log = breakageLog()
cutoff = 0.074e-3  # Hardin's: the silt limit
Br = relativeBreakage(before, after, cutoff)
mass1 = after[1].sum()
peak = max(s for e, s, k, c in path)
print('end          strain %.4f, stress %.2f MPa (peak %.2f MPa), %d steps, %.0f s' % (
    path[-1][0], path[-1][1] / 1e6, peak / 1e6, O.iter, time.time() - started))
print('grains       %d -> %d after %d splits; mass before %.6e kg, after %.6e kg (relative change %.1e)' % (
    len(before[0]), len(after[0]), len(log), mass0, mass1, abs(mass1 - mass0) / mass0))
for name, (d, m) in (('before', before), ('after', after)):
    order = np.argsort(d)
    finer = np.cumsum(m[order]) / m.sum()
    print('grading      %-6s d10 %.2f mm, d50 %.2f mm, smallest %.2f mm' % (
        name, 1e3 * np.interp(0.1, finer, d[order]), 1e3 * np.interp(0.5, finer, d[order]), 1e3 * d.min()))
print('breakage     Hardin B_r %.4f (cutoff %.3f mm)' % (Br, cutoff * 1e3))

if figures:
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    from matplotlib.collections import PatchCollection
    from matplotlib.patches import Circle
    os.makedirs(figures, exist_ok=True)
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(10, 4))
    for name, (d, m), style in (('before', before, '-'), ('after', after, '--')):
        order = np.argsort(d)
        a1.step(1e3 * d[order], 100 * np.cumsum(m[order]) / m.sum(), style, where='post',
                label='%s: %d grains' % (name, len(d)))
    a1.set_xscale('log')
    a1.set_xlabel('grain size: diameter of the sphere of its volume (mm)')
    a1.set_ylabel('mass finer (%)')
    a1.set_title('Grading, Hardin B_r = %.3f' % Br)
    a1.legend(loc='upper left')
    p = np.array(path)
    a2.plot(100 * p[:, 0], p[:, 1] / 1e6, lw=1, label='vertical stress')
    a2.set_xlabel('vertical strain (%)')
    a2.set_ylabel('vertical stress (MPa)')
    b2 = a2.twinx()
    b2.plot(100 * p[:, 0], p[:, 2], color='C3', lw=1)
    b2.set_ylabel('splits so far', color='C3')
    a2.set_title('One-dimensional compression: %d splits' % len(log))
    fig.tight_layout()
    fig.savefig(os.path.join(figures, 'oedometer_grading.png'), dpi=120)

    fig, axes = plt.subplots(1, 2, figsize=(9, 4.6), sharey=True)
    for ax, ss, title in ((axes[0], state['section'], 'at the preload, %d grains' % len(before[0])),
                          (axes[1], spheres(), 'at the end, %d grains' % len(after[0]))):
        # the spheres' circles in the vertical mid-plane y = W/2, a colour per clump
        cut = [(p, np.sqrt(r * r - (p[1] - W / 2) ** 2), k) for p, r, k in ss if abs(p[1] - W / 2) < r]
        owners = sorted(set(k for p, r, k in cut))
        colours = {k: plt.cm.tab20(i % 20) for i, k in enumerate(owners)}
        ax.add_collection(PatchCollection([Circle((p[0] * 1e3, p[2] * 1e3), r * 1e3) for p, r, k in cut],
                                          facecolors=[colours[k] for p, r, k in cut], alpha=0.6, edgecolors='k',
                                          linewidths=0.3))
        ax.set_aspect('equal')
        ax.set_xlim(0, W * 1e3)
        ax.set_ylim(0, state['H'] * 1e3 + 0.5)
        ax.axhline(state['H'] * 1e3 if ss is state['section'] else height() * 1e3, color='0.3', lw=1.5)
        ax.set_xlabel('x (mm)')
        ax.set_title(title)
    axes[0].set_ylabel('z (mm)')
    fig.suptitle('Section y = %.0f mm: the spheres cut by the plane, a colour per grain; grey: the lid' % (W * 5e2))
    fig.tight_layout()
    fig.savefig(os.path.join(figures, 'oedometer_section.png'), dpi=120)

# checks that can fail: grains broke under load, the grading got finer, mass was kept, every split was due
assert peak > 1e6, 'the sample never carried load (peak %g Pa)' % peak
assert log, 'no grain broke'
assert all(ev['sigma'] >= ev['strength'] for ev in log)
assert len(after[0]) == len(before[0]) + sum(len(ev['pieces']) - 1 for ev in log)
assert abs(mass1 - mass0) < 1e-12 * mass0, (mass0, mass1)
assert all(abs(sum(ev['volumes']) - ev['parentVolume']) < 1e-12 * ev['parentVolume'] for ev in log)
d50 = [np.interp(0.5, np.cumsum(m[np.argsort(d)]) / m.sum(), np.sort(d)) for d, m in (before, after)]
assert d50[1] < d50[0] and Br > 0, (d50, Br)
print('oedometer_crushing: checks passed')
