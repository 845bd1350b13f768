"""What every bench row records beside its figures: the date, the commit, the machine and its load (CONVENTIONS.md:
results as data). Imported by the YADE benches (yade -n -x bench/NAME.py, run from the repository root)."""
import datetime
import os
import subprocess

HERE = os.path.dirname(os.path.abspath(__file__))


def commit():
    """The checked-out commit, short."""
    try:
        return subprocess.run(['git', '-C', HERE, 'rev-parse', '--short', 'HEAD'], capture_output=True, text=True,
                              check=True).stdout.strip()
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
