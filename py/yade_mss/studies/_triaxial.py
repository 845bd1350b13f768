"""The triaxial test of clumps in YADE: a periodic cell of grains at random orientations, isotropic compaction to
the confining pressure, then shearing along z at a strain rate set by the inertial number, drained (constant
lateral stress) or undrained (constant volume). Compression positive in everything it returns.

Assumptions, stated once: a periodic cell (no walls: no boundary effects, no membrane); the linear law of
``Law2_ScGeom_FrictPhys_CundallStrack`` between member spheres (YADE's default for ``FrictMat``); no gravity;
YADE's local (non-viscous) damping in ``NewtonIntegrator``; a dense state made by compacting without friction
and a loose one with it (the usual DEM way to span void ratios). The strain rate comes from the inertial
number I = rate d sqrt(rho / p) (GDR MiDi 2004) so that every sphere count shears equally slowly; the time step
is YADE's ``PWaveTimeStep`` (the smallest member sets it), so what a sphere count costs shows in the steps.
"""

import json
import math
import os
import time

import numpy as np

from ..base import atomicWrite, integer, number, randomRotation
from ..grains import optionTable
from ..yade import MssTemplate, contactStiffnessEngine, yadeModules
from ._analysis import COLUMNS, derived

# Compaction is done when the mean stress is within this of the goal and the unbalanced force under the bound.
COMPACTION_STRESS_TOL = 0.01
COMPACTION_UNBALANCED = 0.01


class TriaxialResult(object):
    """What :func:`triaxial` returns.

    :param records: the shearing records (dicts of :data:`COLUMNS`)
    :param compaction: the compaction's figures (dict)
    :param cost: the run's cost (dict)
    :param options: the options it ran with (dict)

    :ivar records: the shearing records, a dict a row with :data:`COLUMNS` (compression positive)
    :ivar compaction: dict: steps, p_Pa, void_ratio, void_ratio_union, unbalanced, seconds
    :ivar derived: dict of :func:`derived` (phi_peak_deg, phi_cs_deg, psi_max_deg, E50_Pa, e0, ...)
    :ivar cost: dict: steps (all), shear_steps, dt_s (the time step), step_s (wall time a step), wall_s,
        spheres (every member), clumps
    :ivar options: the options it ran with
    """

    def __init__(self, records, compaction, cost, options):
        self.records = records
        self.compaction = compaction
        self.cost = cost
        self.options = options
        self.derived = derived(records)

    def summary(self):
        """One row of summary.csv: n, the derived figures, the compaction and the cost."""
        row = dict(n=self.options.get('n'))
        row.update(self.derived)
        row.update(compaction_steps=self.compaction['steps'], steps=self.cost['steps'], dt_s=self.cost['dt_s'],
                   step_s=self.cost['step_s'], wall_s=self.cost['wall_s'], spheres=self.cost['spheres'],
                   clumps=self.cost['clumps'])
        return row

    def __repr__(self):
        d = self.derived
        return '<TriaxialResult n=%s phi_peak %.1f deg, phi_cs %.1f deg, e0 %.3f, %d steps>' % (
            self.options.get('n'), d['phi_peak_deg'], d['phi_cs_deg'], d['e0'], self.cost['steps'])


def _checked(templates, weights, o):
    f = 'triaxial'
    templates = list(templates) if isinstance(templates, (list, tuple)) else [templates]
    if not templates or not all(isinstance(t, MssTemplate) for t in templates):
        raise TypeError('%s: templates must be MssTemplate objects (mssTemplate makes them), got %r' % (f, templates))
    if weights is None:
        weights = [1.0] * len(templates)
    if isinstance(weights, (str, bytes)) or not hasattr(weights, '__len__') or len(weights) != len(templates):
        raise ValueError('%s: weights must be a number a template (%d), got %r' % (f, len(templates), weights))
    w = np.array([number(f, 'weights', x, 0.0) for x in weights])
    if w.sum() <= 0:
        raise ValueError('%s: weights must not all be 0' % f)
    # the option table's types and ranges, as mss triaxial and triaxialStudy check them (one source)
    o.update(optionTable.collect(f, 'triaxial', {k: v for k, v in o.items() if k not in ('spacing', 'n')}))
    if o['spacing'] is not None:
        o['spacing'] = number(f, 'spacing', o['spacing'])
        if not o['spacing'] > 0:
            raise ValueError('%s: spacing must be > 0, got %r' % (f, o['spacing']))
    return templates, w / w.sum()


def clearance(template):
    """The radius about the grain's centre of mass that holds every sphere of *template* (scaled): grains whose
    centres of mass are twice the largest of these apart never overlap, whatever their orientations."""
    r = template.result
    c = r.targetMass.centroid if r.targetMass is not None else template.unionCentroid
    return template.scale * r.boundingRadius(c)


def placements(n, spacing, weights, seed):
    """Where the grains go and how they turn: a cubic lattice of *spacing* in a periodic cell, n of its sites
    at random, a uniformly random rotation and a template drawn by *weights* each. The draws depend on the seed
    and n only, so the same specimen (places, orientations, which grain) comes out for any sphere count.

    :return: (cell edge, centres (n, 3), rotations (n, 3, 3), template indices (n,))
    """
    rng = np.random.default_rng(seed)
    k = int(math.ceil(n ** (1.0 / 3.0) - 1e-9))
    sites = np.array([(i, j, m) for i in range(k) for j in range(k) for m in range(k)], dtype=float)
    chosen = sites[rng.permutation(len(sites))[:n]]
    rotations = np.array([randomRotation(rng) for _ in range(n)])
    which = rng.choice(len(weights), size=n, p=weights)
    return k * spacing, (chosen + 0.5) * spacing, rotations, which


class _Scene(object):
    """The specimen in YADE and what the records need of it."""

    def __init__(self, templates, weights, o):
        w, O, me = yadeModules()
        if len(O.bodies):
            raise ValueError('triaxial: the scene holds %d bodies; the test builds its own specimen (O.reset() '
                             'first)' % len(O.bodies))
        spacing = o['spacing'] or 2.0 * max(clearance(t) for t in templates) * 1.001
        L, centres, rotations, which = placements(o['grains'], spacing, weights, o['seed'])
        O.periodic = True
        O.cell.setBox(L, L, L)
        friction = 0.0 if o['state'] == 'dense' else o['frictionAngle']
        self.material = O.materials.append(w.FrictMat(young=o['young'], poisson=o['poisson'], density=o['density'],
                                                      frictionAngle=friction, label='mssTriaxialGrains'))
        self.clumps, union = [], 0.0
        for c, R, k in zip(centres, rotations, which):
            t = templates[k]
            r = t.result
            target = r.targetMass.centroid if r.targetMass is not None else t.unionCentroid
            centre = c - t.scale * R.dot(target - t.unionCentroid)
            self.clumps.append(t.place(centre, R, material=self.material,
                                       contactStiffness=o['contactStiffness'])[0])
            union += r.unionVolume() * t.scale ** 3
        self.solid = sum(O.bodies[c].state.mass for c in self.clumps) / o['density']
        self.union = union
        self.diameter = float(np.mean([2 * templates[k].equivalentRadius for k in which]))
        self.spheres = sum(len(templates[k].result) for k in which)


def _engines(o):
    w = yadeModules()[0]  # YADE's utils holds its classes too
    stiffness = [contactStiffnessEngine(every=STIFFNESS_EVERY)] if o.get('contactStiffness') == 'grain' else []
    return [w.ForceResetter(), w.InsertionSortCollider([w.Bo1_Sphere_Aabb()]),
            w.InteractionLoop([w.Ig2_Sphere_Sphere_ScGeom()], [w.Ip2_FrictMat_FrictMat_FrictPhys()],
                              [w.Law2_ScGeom_FrictPhys_CundallStrack()])] + stiffness + [
            w.PyRunner(command='import yade_mss.studies._triaxial as m; m.servoStep()', iterPeriod=SERVO_STEPS,
                       label='mssTriaxialServo'),
            w.NewtonIntegrator(damping=o['damping'])]


# The stress servo: on a stress-controlled axis the cell's strain rate closes the stress error over SERVO_RELAX
# steps at the packing's stiffness (estimated from its contacts, affinely: an upper bound, so the servo errs
# slow), at most the largest rate given; set every SERVO_STEPS steps from getStress(). YADE's
# PeriTriaxController stalled here (12 frictionless clumps held at 79 / 91 / 100 kPa for 40,000 steps while it
# aimed at 100 kPa on each axis); a servo whose gain ignored the stiffness ran into a limit cycle at jamming.
SERVO_STEPS = 10
STIFFNESS_EVERY = 10  # steps between the passes of contactStiffness='grain' (bench/pair_stiffness.py)
SERVO_RELAX = 200


def stiffness(O):
    """The packing's diagonal stiffness d sigma_ii / d eps_ii (Pa), affine: (1/V) sum kn l^2 n_i^4 over the
    contacts (l the distance between the sphere centres, n the normal)."""
    k = np.zeros(3)
    for i in O.interactions:
        if i.isReal:
            g = i.geom
            n = np.array([g.normal[0], g.normal[1], g.normal[2]])
            length = g.refR1 + g.refR2 - g.penetrationDepth
            k += i.phys.kn * length * length * n ** 4
    return k / O.cell.volume


class _Servo(object):
    """The servo's goals and rates, run by a PyRunner every SERVO_STEPS steps inside the simulation's loop
    (O.run in chunks of 10 steps cost 40 ms a chunk in waiting: 8 times the steps' own time). The stiffness is
    estimated again every STIFFNESS_CALLS calls (a Python pass over every interaction: every 200 steps it cost
    18 % of a step of 200 clumps of 10 spheres; every 1000, under 4 %)."""
    STIFFNESS_CALLS = 100

    def __init__(self):
        self.set((None,) * 3, (0.0,) * 3)

    def set(self, goals, rates):
        """goals[i]: a stress (Pa, compression positive; rates[i] the largest strain rate) or None (rates[i] the
        compression rate the axis keeps)."""
        self.goals, self.rates, self.calls, self.stiff = tuple(goals), tuple(rates), 0, np.zeros(3)

    def step(self):
        utils, O, me = yadeModules()
        if self.calls % self.STIFFNESS_CALLS == 0 and any(g is not None for g in self.goals):
            self.stiff = stiffness(O)
        self.calls += 1
        sigma = _stress(utils)
        v = [0.0, 0.0, 0.0]
        for i in range(3):
            g, r = self.goals[i], self.rates[i]
            if g is None:
                v[i] = -r
                continue
            want = (g - sigma[i, i]) / (self.stiff[i] * SERVO_RELAX * O.dt) if self.stiff[i] > 0 else np.sign(
                g - sigma[i, i]) * r
            v[i] = -max(-r, min(r, want))
        O.cell.velGrad = _diagonal(*v)


SERVO = _Servo()


def servoStep():
    """What the test's PyRunner calls."""
    SERVO.step()


def _stress(utils):
    """The stress tensor, compression positive (YADE's getStress: Love-Weber over the cell, tension positive)."""
    s = utils.getStress()
    return -np.array([[s[i, j] for j in range(3)] for i in range(3)])


def _coordination(O, clumpOf):
    """Contacts a grain: distinct pairs of clumps in contact, twice over the clumps."""
    pairs = set()
    for i in O.interactions:
        if i.isReal:
            a, b = clumpOf.get(i.id1, i.id1), clumpOf.get(i.id2, i.id2)
            if a != b:
                pairs.add((min(a, b), max(a, b)))
    return 2.0 * len(pairs) / max(1, len(set(clumpOf.values())))


class _Run(object):
    """One test's state: what a checkpoint holds beside the scene (O.save)."""

    def __init__(self, o):
        self.o = o
        self.phase = 'compaction'
        self.records = []
        self.compaction = None
        self.shearStart = None  # step, cell edges and volume at the start of shearing
        self.started = time.time()
        self.wall = 0.0  # seconds of earlier sessions (a resumed run)
        self.rate = None
        self.compactionRate = None
        self.geometry = None  # solid, union, diameter, spheres, clumps, clumpOf

    def state(self):
        return dict(phase=self.phase, records=self.records, compaction=self.compaction, shearStart=self.shearStart,
                    wall=self.wall + time.time() - self.started, rate=self.rate,
                    compactionRate=self.compactionRate, geometry=self.geometry,
                    options=self.o)


def _save(run, folder, O):
    """The scene and the run's state, each written whole (a stop mid-write leaves the previous pair)."""
    if folder is None:
        return
    scene = os.path.join(folder, 'checkpoint.yade.gz')
    atomicWrite(scene, lambda tmp: O.save(tmp), 'triaxial')
    text = json.dumps(run.state())

    def write(tmp):
        with open(tmp, 'w') as f:
            f.write(text)
    atomicWrite(os.path.join(folder, 'checkpoint.json'), write, 'triaxial')


def _resume(run, folder, O):
    """Loads the checkpoint of *folder* into *run* when it is of the same options; True when it did."""
    if folder is None:
        return False
    scene, state = os.path.join(folder, 'checkpoint.yade.gz'), os.path.join(folder, 'checkpoint.json')
    if not (os.path.isfile(scene) and os.path.isfile(state)) or os.path.getsize(state) > (256 << 20):
        return False
    try:
        with open(state) as f:
            s = json.load(f)
    except ValueError:
        return False
    if s.get('options') != run.o:
        return False
    O.load(scene)
    run.phase, run.records, run.compaction = s['phase'], s['records'], s['compaction']
    run.shearStart, run.wall, run.rate, run.geometry = s['shearStart'], s['wall'], s['rate'], s['geometry']
    run.compactionRate = s['compactionRate']
    run.geometry['clumpOf'] = {int(k): v for k, v in run.geometry['clumpOf'].items()}
    return True


def _record(run, O, utils):
    o, g, s0 = run.o, run.geometry, run.shearStart
    sigma = _stress(utils)
    principal = np.sort(np.linalg.eigvalsh(0.5 * (sigma + sigma.T)))[::-1]
    edges = [O.cell.hSize[i, i] for i in range(3)]
    volume = O.cell.volume
    p = float(np.trace(sigma) / 3.0)
    lateral = 0.5 * (sigma[0, 0] + sigma[1, 1])
    q = float(sigma[2, 2] - lateral)
    rate = run.rate
    row = dict(n=o.get('n'), phase='shear', step=O.iter - s0['step'], time_s=O.time - s0['time'],
               axial_strain=1.0 - edges[2] / s0['edges'][2], volumetric_strain=1.0 - volume / s0['volume'],
               sigma1_Pa=float(principal[0]), sigma2_Pa=float(principal[1]), sigma3_Pa=float(principal[2]),
               sigma_axial_Pa=float(sigma[2, 2]), sigma_lateral_Pa=float(lateral), p_Pa=p, q_Pa=q,
               q_over_p=q / p if p > 0 else float('nan'), void_ratio=volume / g['solid'] - 1.0,
               void_ratio_union=volume / g['union'] - 1.0, coordination=_coordination(O, g['clumpOf']),
               unbalanced=float(utils.unbalancedForce()),
               inertial_number=rate * g['diameter'] * math.sqrt(o['density'] / p) if p > 0 else float('inf'))
    assert tuple(row) == COLUMNS
    run.records.append(row)
    return row


def _compact(run, O, utils, progress, folder, budget):
    """Isotropic compaction to the confining pressure; raises RuntimeError, saying what to change, when it
    does not get there within *budget* steps."""
    o = run.o
    p0 = o['confining']
    chunk = 500
    last = time.time()
    while True:
        sigma = _stress(utils)
        p = float(np.trace(sigma) / 3.0)
        unb = float(utils.unbalancedForce())
        if abs(p / p0 - 1.0) <= COMPACTION_STRESS_TOL and unb <= COMPACTION_UNBALANCED and O.iter > chunk:
            break
        if O.iter >= budget:
            raise RuntimeError(
                'triaxial: the compaction did not reach the confining pressure in %d steps (p %.4g Pa of %.4g, '
                'unbalanced force %.3g; done means within %g%% and under %g): give it more steps '
                '(compactionSteps / --compaction-steps), fewer grains, or a larger damping'
                % (budget, p, p0, unb, 100 * COMPACTION_STRESS_TOL, COMPACTION_UNBALANCED))
        SERVO.set((p0,) * 3, (run.compactionRate,) * 3)
        O.run(chunk, True)
        if progress is not None:
            progress('compaction', min(0.99, max(0.0, p / p0)), 'p %.3g kPa, unbalanced %.2g' % (p / 1e3, unb))
        if folder is not None and time.time() - last > 60:
            _save(run, folder, O)
            last = time.time()
    g = run.geometry
    run.compaction = dict(steps=O.iter, p_Pa=p, void_ratio=O.cell.volume / g['solid'] - 1.0,
                          void_ratio_union=O.cell.volume / g['union'] - 1.0, unbalanced=unb)


def _startShear(run, O):
    """Friction on (a dense state was compacted without it), then strain from here, at the chosen rate."""
    o = run.o
    mat = O.materials[run.geometry['material']]
    mat.frictionAngle = o['frictionAngle']
    tan = math.tan(o['frictionAngle'])
    for i in O.interactions:
        if i.isReal:
            i.phys.tangensOfFrictionAngle = tan
    O.cell.trsf = _identity()
    run.shearStart = dict(step=O.iter, time=O.time, edges=[O.cell.hSize[i, i] for i in range(3)],
                          volume=O.cell.volume)
    run.phase = 'shear'


def _shearChunk(run, O, utils, steps):
    """*steps* of shearing: undrained at constant volume (a velocity gradient of zero trace), drained with the
    lateral stresses held by the servo (its largest lateral rate 5 times the axial one)."""
    o, rate = run.o, run.rate
    if o['undrained']:
        SERVO.set((None,) * 3, (-0.5 * rate, -0.5 * rate, rate))
    else:
        SERVO.set((o['confining'], o['confining'], None), (5 * rate, 5 * rate, rate))
    O.run(steps, True)


def _identity():
    return yadeModules()[2].Matrix3.Identity


def _diagonal(a, b, c):
    return yadeModules()[2].Matrix3(a, 0, 0, 0, b, 0, 0, 0, c)


def _shear(run, O, utils, progress, folder):
    o = run.o
    every = max(1, int(round(o['strain'] / o['records'] / (run.rate * O.dt))))
    last = time.time()
    if not run.records:
        _record(run, O, utils)
    while run.records[-1]['axial_strain'] < o['strain']:
        _shearChunk(run, O, utils, every)
        row = _record(run, O, utils)
        if not all(math.isfinite(row[k]) for k in ('p_Pa', 'q_Pa', 'axial_strain')) or row['p_Pa'] <= 0:
            raise RuntimeError('triaxial: the specimen stopped carrying load at axial strain %.4g (p %.4g Pa)'
                               % (row['axial_strain'], row['p_Pa']))
        if progress is not None:
            progress('shear', row['axial_strain'] / o['strain'], 'strain %.3g, q/p %.3f' % (row['axial_strain'],
                                                                                           row['q_over_p']))
        if folder is not None and time.time() - last > 60:
            _save(run, folder, O)
            last = time.time()


def triaxial(templates, weights=None, grains=200, confining=1e5, state='dense', strain=0.2, undrained=False,
             seed=1, density=2650.0, young=1e8, poisson=0.3, frictionAngle=0.5, inertialNumber=5e-4, damping=0.2,
             records=200, spacing=None, compactionSteps=None, contactStiffness='spheres', checkpoint=None,
             progress=None, n=None):
    """Runs a triaxial test of clumps in the current (empty) YADE scene and returns its :class:`TriaxialResult`.

    :param templates: :class:`MssTemplate` objects (:func:`mssTemplate` makes them), in SI units
    :param weights: each template's share of the grains (default: equal)
    :param int grains: clumps in the periodic cell
    :param float confining: the confining pressure, Pa (compaction goal; the lateral stress while drained)
    :param str state: 'dense' (compacted without friction) or 'loose' (compacted with it)
    :param float strain: the axial strain at which shearing stops
    :param bool undrained: constant volume while sheared (default: drained, constant lateral stress)
    :param int seed: the specimen's places, orientations and grains (the same for any sphere count)
    :param float density: kg/m^3
    :param float young: the members' Young's modulus, Pa (FrictMat)
    :param float poisson: FrictMat's poisson (the tangential over normal stiffness)
    :param float frictionAngle: radians, the contacts' friction angle while sheared
    :param float inertialNumber: I = rate d sqrt(rho / p) at the confining pressure: sets the strain rate
    :param float damping: NewtonIntegrator's local damping
    :param int records: records over the strain
    :param float spacing: the lattice's spacing (default: twice the largest clearance of the templates);
        give the same for every sphere count so that the places agree
    :param int compactionSteps: give up the compaction after this many steps (default: 200,000 + 50 a grain)
    :param str contactStiffness: 'spheres' (YADE's own) or 'grain' (one contact of the grains' stiffness a pair
        of clumps, whatever the sphere count: :func:`contactStiffnessEngine`, a pass every 10 steps)
    :param str checkpoint: a folder: the run saves itself there (``O.save``) and resumes from it
    :param progress: called as progress(phase, fraction, text) after each chunk of steps
    :param n: the sphere count the records are labelled with (default: the templates' largest)
    :return: :class:`TriaxialResult`
    """
    o = dict(grains=grains, confining=confining, state=state, strain=strain, undrained=undrained, seed=seed,
             density=density, young=young, poisson=poisson, frictionAngle=frictionAngle,
             inertialNumber=inertialNumber, damping=damping, records=records, spacing=spacing,
             compactionSteps=compactionSteps, contactStiffness=contactStiffness)
    templates, w = _checked(templates, weights, o)
    if checkpoint is not None and not isinstance(checkpoint, (str, os.PathLike)):
        raise TypeError('triaxial: checkpoint must be a folder\'s path, got %r' % (checkpoint,))
    if progress is not None and not callable(progress):
        raise TypeError('triaxial: progress must be a function progress(phase, fraction, text), got %r' % (progress,))
    o['n'] = integer('triaxial', 'n', n, 1) if n is not None else max(len(t.result) for t in templates)
    utils, O, me = yadeModules()
    run = _Run(o)
    if checkpoint is not None:
        os.makedirs(checkpoint, exist_ok=True)
    if not _resume(run, checkpoint, O):
        scene = _Scene(templates, w, o)
        clumpOf = {}
        for c in scene.clumps:
            for m in O.bodies[c].shape.members.keys():
                clumpOf[m] = c
        run.geometry = dict(solid=scene.solid, union=scene.union, diameter=scene.diameter, spheres=scene.spheres,
                            clumps=len(scene.clumps), clumpOf=clumpOf, material=scene.material)
        run.rate = o['inertialNumber'] / (scene.diameter * math.sqrt(density / confining))
        dt = 0.5 * utils.PWaveTimeStep()
        O.dt = dt
        # compaction: at most a strain of 5e-5 a step (neighbours close by a twentieth of a grain in 1000 steps)
        run.compactionRate = 5e-5 / dt
        O.engines = _engines(o)
    budget = o['compactionSteps'] or 200000 + 50 * o['grains']
    try:
        if run.phase == 'compaction':
            _compact(run, O, utils, progress, checkpoint, budget)
            _startShear(run, O)
            _save(run, checkpoint, O)
        _shear(run, O, utils, progress, checkpoint)
    except KeyboardInterrupt:
        _save(run, checkpoint, O)
        raise
    wall = run.wall + time.time() - run.started
    steps = O.iter
    cost = dict(steps=steps, shear_steps=steps - run.shearStart['step'], dt_s=O.dt, step_s=wall / max(1, steps),
                wall_s=wall, spheres=run.geometry['spheres'], clumps=run.geometry['clumps'])
    run.phase = 'done'
    _save(run, checkpoint, O)
    return TriaxialResult(run.records, run.compaction, cost, o)
