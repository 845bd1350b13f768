"""The sphere-count study (``mss triaxial``, :func:`triaxialStudy`): the same specimen (the same grains at the same
places and orientations) tested at each sphere count, the counts side by side in YADE processes of their own
(``yade -n -x``), or as tasks on a Dask cluster; then the records, the summary, the pictures and the report.

OUT/ holds triaxial.csv (every record), summary.csv and summary.json (a row a count), curves.png, sphere_count.png
(with two counts or more), report.html, options.json, templates/ (each count's spheres, .npz) and runs/nN/ (each
count's task, checkpoint and result: a rerun skips what is done and resumes what is not).
"""

import csv
import hashlib
import io
import json
import math
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time

import numpy as np

from ..base import atomicWrite, flag, integer, number, refuseLinkedFolders, restoreSignals, split, stopOnce
from ..grains import GENERATE_OPTIONS, MssResult, optionTable
from ..specimens import checkScheduler, clusterSecurity, freeCores
from ._analysis import COLUMNS, derived
from ._inputs import resolve
from ._report import writeReport

TEST_OPTIONS = ('grains', 'confining', 'state', 'strain', 'undrained', 'seed', 'density', 'young', 'poisson',
                'frictionAngle', 'inertialNumber', 'damping', 'records', 'compactionSteps', 'contactStiffness')
# the option table's defaults (mss triaxial --help shows the same)
TEST_DEFAULTS = {k: optionTable.default(k, 'triaxial') for k in TEST_OPTIONS}
SUMMARY = ('n', 'phi_peak_deg', 'phi_cs_deg', 'psi_max_deg', 'e0', 'e0_union', 'E50_Pa', 'strain_at_peak',
           'q_peak_Pa', 'p_peak_Pa', 'dvol_rate_end', 'I_max', 'unbalanced_median', 'quasi_static', 'strain_end',
           'peak_reached', 'critical_state',
           'compaction_steps', 'steps', 'dt_s', 'step_s', 'wall_s', 'spheres', 'clumps', 'smallest_radius_m',
           'dice_mean')
# The work model (seconds on a 2-core machine, two counts side by side): a step costs a fixed part and a part a
# sphere, and compaction takes about this many steps, fitted to the manual's study (80 grains of 5 to 40 spheres:
# 0.31 ms a step at 400 spheres, 1.49 ms at 3,200; compaction 35,500 to 43,000 steps).
STEP_SECONDS_PER_SPHERE = 4.3e-7
STEP_SECONDS_FIXED = 1.4e-4
COMPACTION_STEPS = 40000


def _counts(nSpheres):
    if isinstance(nSpheres, str):
        try:
            nSpheres = [int(x) for x in nSpheres.split(',') if x.strip()]
        except ValueError:
            raise ValueError('triaxial: nSpheres must be counts separated by commas (5,10,20), got %r' % nSpheres)
    if not isinstance(nSpheres, (list, tuple)):
        nSpheres = [nSpheres]
    out = sorted(set(integer('triaxial', 'nSpheres', n, 1, 65535) for n in nSpheres))
    if not out:
        raise ValueError('triaxial: give at least one sphere count')
    return out


def _yade():
    exe = os.environ.get('MSS_YADE') or shutil.which('yade')
    if not exe:
        raise RuntimeError('triaxial: YADE is not installed (Debian: apt-get install yade): the test runs in it')
    return exe


def _digest(task, results):
    h = hashlib.sha256(json.dumps(task, sort_keys=True).encode())
    for r in results:
        h.update(np.ascontiguousarray(r.centers).tobytes())
        h.update(np.ascontiguousarray(r.radii).tobytes())
    return h.hexdigest()


def _writeText(path, text):
    def write(tmp):
        with open(tmp, 'w') as f:
            f.write(text)
    atomicWrite(path, write, 'triaxial')


def estimate(n, results, weights, o):
    """Seconds one count's test takes on this project's 2-core machine (the work model above), and its steps."""
    w = np.asarray(weights, dtype=float) / np.sum(weights)
    spheres = o['grains'] * float(np.dot(w, [len(r) for r in results]))
    rmin = min(float(r.radii.min()) for r in results)
    d = float(np.dot(w, [2 * (3 * r.targetMass.volume / (4 * math.pi)) ** (1 / 3.) for r in results]))
    dt = 0.5 * rmin * math.sqrt(o['density'] / o['young'])
    rate = o['inertialNumber'] / (d * math.sqrt(o['density'] / o['confining']))
    steps = COMPACTION_STEPS + o['strain'] / (rate * dt)
    return steps * (STEP_SECONDS_FIXED + STEP_SECONDS_PER_SPHERE * spheres), steps


class _Progress(object):
    """One line on standard error over every running count: phase, fraction, time left (a terminal: redrawn each
    second; otherwise a line every 10 s)."""

    def __init__(self, quiet):
        self.quiet = quiet
        self.tty = sys.stderr.isatty()
        self.last = 0.0
        self.start = time.time()

    def show(self, states, force=False):
        if self.quiet:
            return
        now = time.time()
        if not force and now - self.last < (1.0 if self.tty else 10.0):
            return
        self.last = now
        parts, left = [], 0.0
        for n, s in sorted(states.items()):
            if s is None:
                parts.append('n=%d waiting' % n)
                continue
            f = 0.3 * s['fraction'] if s['phase'] == 'compaction' else 0.3 + 0.7 * s['fraction']
            if s['phase'] == 'done':
                f = 1.0
            if 0.05 < f < 1 and s.get('elapsed'):  # a count just begun says nothing of its pace yet
                left = max(left, s['elapsed'] * (1 - f) / f)
            parts.append('n=%d %s %d%%' % (n, s['phase'], int(100 * f)))
        line = 'triaxial: %s | %s elapsed%s' % (' | '.join(parts), _clock(now - self.start),
                                               ', about %s left' % _clock(left) if left > 0 else '')
        if self.tty:
            sys.stderr.write('\r' + line[:200].ljust(120))
        else:
            sys.stderr.write(line + '\n')
        sys.stderr.flush()

    def done(self):
        if self.tty and not self.quiet:
            sys.stderr.write('\n')


def _clock(s):
    s = int(s)
    return '%d:%02d:%02d' % (s // 3600, s // 60 % 60, s % 60) if s >= 3600 else '%d:%02d' % (s // 60, s % 60)


def _readJson(path, limit=256 << 20):
    try:
        if os.path.getsize(path) > limit:
            return None
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


def _runLocal(tasks, outdir, workers, progress):
    """Each task in a YADE process of its own, *workers* at once; a count's process that fails names why."""
    runner = os.path.join(os.path.dirname(os.path.abspath(__file__)), '_runner.py')
    env = dict(os.environ)
    top = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    env['PYTHONPATH'] = top + (os.pathsep + env['PYTHONPATH'] if env.get('PYTHONPATH') else '')
    env.setdefault('OMP_NUM_THREADS', '1')
    todo = list(tasks)
    running, failed = {}, {}
    states = {t['n']: None for t in tasks}
    try:
        while todo or running:
            while todo and len(running) < workers:
                t = todo.pop(0)
                folder = os.path.abspath(os.path.join(outdir, 'runs', 'n%d' % t['n']))
                log = open(os.path.join(folder, 'yade.log'), 'w')
                running[t['n']] = (subprocess.Popen([_yade(), '-n', '-x', runner, os.path.join(folder, 'task.json')],
                                                    stdout=log, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL,
                                                    env=env, cwd=folder), log, folder)
            time.sleep(0.5)
            for n, (proc, log, folder) in list(running.items()):
                s = _readJson(os.path.join(folder, 'progress.json'))
                if s is not None:
                    states[n] = s
                if proc.poll() is not None:
                    log.close()
                    del running[n]
                    if proc.returncode == 130:
                        raise KeyboardInterrupt
                    if proc.returncode != 0:
                        err = _readJson(os.path.join(folder, 'error.json')) or {}
                        failed[n] = err.get('error') or 'YADE exited with status %d (runs/n%d/yade.log)' % (
                            proc.returncode, n)
                    else:
                        states[n] = dict(phase='done', fraction=1.0)
            progress.show(states)
    except KeyboardInterrupt:  # a second signal is ignored till the study has written what it has (stopOnce)
        for proc, log, folder in running.values():  # each saves its checkpoint and exits
            if proc.poll() is None:
                proc.send_signal(signal.SIGINT)
        for proc, log, folder in running.values():
            try:
                proc.wait(timeout=60)
            except subprocess.TimeoutExpired:
                proc.kill()
            log.close()
        raise
    finally:
        progress.show(states, force=True)
        progress.done()
    return failed


def _runOnDask(payload):
    """A Dask task: one count's test in a YADE process on the worker, in a scratch folder (the templates travel
    in the task); returns the result or the error."""
    folder = tempfile.mkdtemp(prefix='mss-triaxial-')
    try:
        task = payload['task']
        for name, data in payload['files'].items():
            with open(os.path.join(folder, name), 'wb') as f:
                f.write(data)
        with open(os.path.join(folder, 'task.json'), 'w') as f:
            json.dump(task, f)
        runner = os.path.join(os.path.dirname(os.path.abspath(__file__)), '_runner.py')
        proc = subprocess.run([_yade(), '-n', '-x', runner, os.path.join(folder, 'task.json')], cwd=folder,
                              stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
        result = _readJson(os.path.join(folder, 'result.json'))
        if result is None:
            err = _readJson(os.path.join(folder, 'error.json')) or {}
            return dict(n=task['n'], error=err.get('error') or 'YADE exited with status %d on the worker: %s' % (
                proc.returncode, proc.stdout.decode(errors='replace')[-400:]))
        return result
    finally:
        shutil.rmtree(folder, ignore_errors=True)


def _runDask(tasks, outdir, scheduler, security, connectTimeout):
    try:
        from distributed import Client, as_completed
    except ImportError:
        raise RuntimeError('triaxial: --scheduler needs Dask (Debian: python3-distributed)')
    try:
        client = Client(scheduler, timeout=connectTimeout, security=security)
    except (OSError, TimeoutError) as e:
        raise RuntimeError('triaxial: the Dask scheduler at %s did not answer within %g s: %s' % (scheduler,
                                                                                                  connectTimeout, e))
    failed = {}
    try:
        payloads = []
        for t in tasks:
            folder = os.path.join(outdir, 'runs', 'n%d' % t['n'])
            files = {}
            for g in t['templates']:
                with open(os.path.join(folder, g['file']), 'rb') as f:
                    files[g['file']] = f.read()
            payloads.append(dict(task=t, files=files))
        for fut in as_completed(client.map(_runOnDask, payloads, pure=False, retries=1)):
            r = fut.result()
            folder = os.path.join(outdir, 'runs', 'n%d' % r['n'])
            if 'error' in r:
                failed[r['n']] = r['error']
            else:
                _writeText(os.path.join(folder, 'result.json'), json.dumps(r))
    finally:
        client.close()
    return failed


def _prepare(grains, counts, gen, o, outdir):
    """Each count's spheres (generated here), the lattice spacing that fits every count, and each count's task."""
    results = {}
    for n in counts:
        results[n] = [g.at(n, gen) for g in grains]
        for r, g in zip(results[n], grains):
            if r.targetMass is None:
                raise ValueError('triaxial: %s: no grain to take the exact mass from' % g.name)
    # the same places for every count: the spacing holds the largest clump of any count
    spacing = 2.0 * 1.001 * max(r.boundingRadius(r.targetMass.centroid) for rs in results.values() for r in rs)
    tasks = []
    for n in counts:
        templates = [dict(file='grain%04d.npz' % k, weight=g.weight, name=g.name) for k, g in enumerate(grains)]
        task = dict(n=n, options=dict(o, spacing=spacing), templates=templates)
        task['digest'] = _digest(task, results[n])
        tasks.append(task)
    return results, tasks


def _writeTask(outdir, task, results):
    """A count's folder: its spheres (.npz) and task.json."""
    folder = os.path.join(outdir, 'runs', 'n%d' % task['n'])
    os.makedirs(folder, exist_ok=True)
    for g, r in zip(task['templates'], results):
        r.save(os.path.join(folder, g['file']))
    _writeText(os.path.join(folder, 'task.json'), json.dumps(task))


def _finished(outdir, task):
    r = _readJson(os.path.join(outdir, 'runs', 'n%d' % task['n'], 'result.json'))
    return r if r is not None and r.get('digest') == task['digest'] else None


def triaxialStudy(inputs, outdir, nSpheres=None, grain=None, workers=None, scheduler=None, security=None,
                  connectTimeout=5.0, maxWork=7200.0, quiet=False, **options):
    """The triaxial test of *inputs*' grains at each sphere count of *nSpheres*, the same specimen each time,
    in YADE processes side by side (``mss triaxial``). Runs in a plain python3 (it starts YADE itself).

    :param inputs: a grain file (mesh or volume; a labelled volume: each label a grain), a folder of grain
        files, a finished ``mss batch`` folder (its grains, regenerated from its scan at each count), or another
        generator's sphere file (with *grain*); or a list of these
    :param outdir: the output folder (a rerun resumes in it)
    :param nSpheres: a count or a list of counts (default 10; a sphere-file input: its own count)
    :param grain: the grain a sphere-file input stands for (its exact mass)
    :param int workers: counts run side by side (default: the free cores)
    :param str scheduler: a Dask scheduler's address: each count a task there
    :param security: Dask's ``distributed.Security`` for a TLS scheduler (default: Dask's configuration)
    :param float connectTimeout: seconds to wait for the scheduler to answer
    :param float maxWork: refuse a study estimated over this many seconds, before it starts
    :param bool quiet: no progress line
    :param options: the test's options (:func:`triaxial`: grains, confining, state, strain, undrained, seed,
        density, young, poisson, frictionAngle, inertialNumber, damping, records, compactionSteps) and every
        generation option (voxelSize, scale, rMin, maxProtrusion, clip, resolution, ...)
    :return: dict: summary (a row a count), records (every record), failed ({n: why}), outdir
    """
    test, gen = split('triaxial', options, TEST_OPTIONS, tuple(k for k in GENERATE_OPTIONS if k != 'nSpheres'),
                      extra=('inputs', 'outdir', 'nSpheres', 'grain', 'workers', 'scheduler', 'security',
                             'connectTimeout', 'maxWork', 'quiet'))
    o = dict(TEST_DEFAULTS, **optionTable.collect('triaxial', 'triaxial', test))
    if not isinstance(outdir, (str, os.PathLike)):
        raise TypeError('triaxial: outdir must be a folder\'s path, got %r' % (outdir,))
    outdir = os.fspath(outdir)
    maxWork = number('triaxial', 'maxWork', maxWork, 0.0)
    connectTimeout = number('triaxial', 'connectTimeout', connectTimeout, 0.0)
    quiet = flag('triaxial', 'quiet', quiet)
    workers = None if workers is None else integer('triaxial', 'workers', workers, 1, 1024)
    counts = _counts(optionTable.default('nSpheres', 'triaxial') if nSpheres is None else nSpheres)
    grains = resolve(inputs, grain, gen)
    fixed = [len(g.fixed) for g in grains if g.fixed is not None]
    if fixed:  # another generator's spheres: their count labels the test
        if nSpheres is not None and len(counts) > 1:
            raise ValueError('triaxial: a sphere file has its own count: give one count (or none) with it')
        counts = [max(fixed)] if len(fixed) == len(grains) else counts
    if os.path.lexists(outdir) and not os.path.isdir(outdir):
        raise ValueError('triaxial: %s exists and is not a folder' % outdir)
    refuseLinkedFolders('triaxial', [outdir])
    security = clusterSecurity(security)
    checkScheduler('triaxial', scheduler, security)
    results, tasks = _prepare(grains, counts, gen, o, outdir)
    weights = [g.weight for g in grains]
    todo = [t for t in tasks if _finished(outdir, t) is None]
    side = workers or (1 if scheduler else min(len(todo) or 1, freeCores()))
    seconds = [estimate(t['n'], results[t['n']], weights, o)[0] for t in todo]
    order = sorted(range(len(todo)), key=lambda i: -seconds[i])  # the longest first: side by side, done sooner
    todo, seconds = [todo[i] for i in order], [seconds[i] for i in order]
    wall = sum(sorted(seconds, reverse=True)[::side]) if seconds else 0.0  # the longest first, side by side
    if wall > maxWork:
        raise ValueError('triaxial: the study would take about %s on a 2-core machine (%s), over maxWork %g s '
                         '(--max-work): fewer grains, a smaller strain, fewer or smaller counts, or raise the limit'
                         % (_clock(wall), ', '.join('n=%d %s' % (t['n'], _clock(s)) for t, s in zip(todo, seconds)),
                            maxWork))
    os.makedirs(outdir, exist_ok=True)
    _writeText(os.path.join(outdir, 'options.json'), json.dumps(dict(
        inputs=[os.fspath(p) for p in (inputs if isinstance(inputs, (list, tuple)) else [inputs])],
        nSpheres=counts, grain=grain, options=o, generate=gen, grains=[g.name for g in grains]), indent=1,
        default=str))
    if not quiet and todo:
        print('triaxial: %d grains of %d kinds, counts %s; %d to run (about %s), %d done before'
              % (o['grains'], len(grains), ','.join(map(str, counts)), len(todo), _clock(wall),
                 len(tasks) - len(todo)), file=sys.stderr)
    for t in todo:
        _writeTask(outdir, t, results[t['n']])
    failed = {}
    interrupted = False
    before = stopOnce((signal.SIGINT,))  # a second Ctrl-C waits for the checkpoints and the files
    try:
        try:
            if todo:
                if scheduler:
                    failed = _runDask(todo, outdir, scheduler, security, connectTimeout)
                else:
                    failed = _runLocal(todo, outdir, side, _Progress(quiet))
        except KeyboardInterrupt:
            interrupted = True
        out = _collect(outdir, tasks, results, weights, failed)
    finally:
        restoreSignals(before)
    if interrupted:
        raise KeyboardInterrupt
    return out


def _partial(outdir, n):
    """The records an unfinished count made (its checkpoint's), for the files of a stopped study."""
    s = _readJson(os.path.join(outdir, 'runs', 'n%d' % n, 'checkpoint.json'))
    return (s or {}).get('records') or []


def _collect(outdir, tasks, results, weights, failed):
    rows, records, unfinished = [], [], []
    for t in tasks:
        n = t['n']
        r = _finished(outdir, t)
        if r is None:
            part = _partial(outdir, n)
            records += part
            if n not in failed:
                unfinished.append(n)
            continue
        records += r['records']
        row = dict(derived(r['records']), n=n)
        row.update(compaction_steps=r['compaction']['steps'], steps=r['cost']['steps'], dt_s=r['cost']['dt_s'],
                   step_s=r['cost']['step_s'], wall_s=r['cost']['wall_s'], spheres=r['cost']['spheres'],
                   clumps=r['cost']['clumps'], smallest_radius_m=min(float(x.radii.min()) for x in results[n]),
                   dice_mean=float(np.mean([x.metrics.get('dice', float('nan')) for x in results[n]])))
        rows.append(row)
    _writeCsv(os.path.join(outdir, 'triaxial.csv'), COLUMNS, records)
    _writeCsv(os.path.join(outdir, 'summary.csv'), SUMMARY, rows)
    _writeText(os.path.join(outdir, 'summary.json'), json.dumps(dict(summary=rows, failed={str(k): v for k, v in
                                                                                           failed.items()},
                                                                     unfinished=unfinished), indent=1))
    writeReport(outdir, rows, records, failed, unfinished)
    return dict(summary=rows, records=records, failed=failed, unfinished=unfinished, outdir=outdir)


def _writeCsv(path, columns, rows):
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=list(columns), extrasaction='ignore', lineterminator='\n')
    w.writeheader()
    for r in rows:
        w.writerow({k: (repr(v) if isinstance(v, float) else v) for k, v in r.items()})
    _writeText(path, buf.getvalue())


def loadTemplates(task, folder):
    """The task's results (MssResult), read back from *folder*."""
    return [MssResult.load(os.path.join(folder, g['file'])) for g in task['templates']]
