"""Generation inside YADE's process when the cores are shared: the femur at resolution 103, 70 spheres, by default
and on one thread, with MSS_BUSY (default 8) busy processes on the machine and without. YADE starts the OpenMP
runtime before yade_mss loads, with waiters that spin: the default must then take the cores others leave free,
never all of them (the bar: at most 1.5x the time of one thread under the same load). Median of 5; prints a
table and appends a row a case to bench/results/yade_load.csv.
Run: yade -n -x bench/yade_load.py   (after bash scripts/setup.sh)"""
import os
import subprocess
import sys
import time

HERE = os.path.abspath('bench')  # yade runs the script with its own __file__: from the repository's root
sys.path.insert(0, HERE)
from batch_scale import appendRows  # noqa: E402

from yade_mss import generate  # noqa: E402

FEMUR = os.path.join(HERE, '..', 'tests', 'data', 'human_femur.stl')
BUSY = int(os.environ.get('MSS_BUSY', '8'))


def median(threads):
    ts = []
    for _ in range(5):
        t = time.perf_counter()
        generate(FEMUR, nSpheres=70, resolution=103, threads=threads)
        ts.append(time.perf_counter() - t)
    return sorted(ts)[2]


def main():
    rows = []
    told = os.environ.get('MSS_OMP_SPINNING')
    print('MSS_OMP_SPINNING=%s (the runtime started before yade_mss: its waiters spin); "not told" unsets it, as '
          'before yade_mss said so' % told)
    print('%6s %10s %12s %12s %8s' % ('busy', 'spinning', 'default s', '1 thread s', 'ratio'))
    for busy in (0, BUSY):
        procs = [subprocess.Popen([sys.executable, '-c', 'while True: pass']) for _ in range(busy)]
        try:
            time.sleep(1.0 if busy else 0.0)
            for say in ([True, False] if told else [False]):
                if say:
                    os.environ['MSS_OMP_SPINNING'] = told
                else:
                    os.environ.pop('MSS_OMP_SPINNING', None)
                load = open('/proc/loadavg').read().split()[0]
                default, one = median(0), median(1)
                print('%6d %10s %12.3f %12.3f %7.2fx   (load %s)' % (busy, 'told' if say else 'not told', default,
                                                                  one, default / one, load), flush=True)
                rows.append([busy, 'told' if say else 'not told', default, one, default / one])
        finally:
            for p in procs:
                p.kill()
            if told:
                os.environ['MSS_OMP_SPINNING'] = told
    print('appended %s' % appendRows('yade_load.csv', ['busy_processes', 'spinning', 'default_s', 'one_thread_s',
                                                       'ratio'], rows))


main()
