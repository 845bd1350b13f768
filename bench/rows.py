"""What every bench row records beside its figures: the date, the commit, the machine and its load (CONVENTIONS.md:
results as data). Imported by the YADE benches (yade -n -x bench/NAME.py, run from the repository root)."""
import datetime
import os
import subprocess

HERE = os.path.dirname(os.path.abspath(__file__))


def commit():
    """The checked-out commit, short; '+dirty' where py/ or pkg/ hold changes it does not (what a bench
    measured is then not that commit)."""
    try:
        head = subprocess.run(['git', '-C', HERE, 'rev-parse', '--short', 'HEAD'], capture_output=True, text=True,
                              check=True).stdout.strip()
        changed = subprocess.run(['git', '-C', os.path.dirname(HERE), 'status', '--porcelain', '--', 'py', 'pkg'],
                                 capture_output=True, text=True, check=True).stdout.strip()
        return head + ('+dirty' if changed else '')
    except (OSError, subprocess.CalledProcessError):
        return 'unknown'


def machine():
    """Cores and CPU model, as bench/lib.sh writes them."""
    model = 'unknown CPU'
    with open('/proc/cpuinfo') as f:
        for line in f:
            if line.startswith('model name'):
                model = ' '.join(line.split(':', 1)[1].replace(',', ' ').split())
                break
    return '%d cores %s' % (os.cpu_count(), model)


def stamp():
    """The columns every row begins with: date, commit, machine, load (the last minute's)."""
    return dict(date=datetime.datetime.now().isoformat(timespec='seconds'), commit=commit(), machine=machine(),
                load=round(os.getloadavg()[0], 2))


def useBuild():
    """Measures this checkout: its build's package (build/py, or MSS_BUILD_PY) first on sys.path and on the
    PYTHONPATH its children and Dask workers inherit. Without it a bench imported the yade_mss that
    scripts/setup.sh installed in /usr/local, of whatever commit set up the machine last, under the row of this
    one. Refuses a build older than the checkout (a Python file that differs from py/'s, a module older than a
    C++ source): run cmake --build build first.

    :return: the build's package folder"""
    import filecmp
    import sys
    repo = os.path.dirname(HERE)
    build = os.environ.get('MSS_BUILD_PY', os.path.join(repo, 'build', 'py'))
    so = os.path.join(build, 'yade_mss', '_mss.so')
    if not os.path.exists(so):
        raise SystemExit('bench: no build at %s: run cmake -S . -B build && cmake --build build (or set '
                         'MSS_BUILD_PY)' % build)
    src = os.path.join(repo, 'py', 'yade_mss')
    for top, _, names in os.walk(src):
        for n in names:
            if n.endswith('.py'):
                p = os.path.join(top, n)
                built = os.path.join(build, 'yade_mss', os.path.relpath(p, src))
                if not os.path.exists(built) or not filecmp.cmp(p, built, shallow=False):
                    raise SystemExit('bench: %s is not the build\'s (%s): run cmake --build build' % (p, built))
    newest = max(os.path.getmtime(os.path.join(top, n)) for d in ('pkg', 'py') for top, _, names in
                 os.walk(os.path.join(repo, d)) for n in names if n.endswith(('.cpp', '.hpp')))
    if os.path.getmtime(so) < newest:
        raise SystemExit('bench: %s is older than a C++ source: run cmake --build build' % so)
    sys.path.insert(0, build)
    os.environ['PYTHONPATH'] = build + (os.pathsep + os.environ['PYTHONPATH'] if os.environ.get('PYTHONPATH') else '')
    return build
