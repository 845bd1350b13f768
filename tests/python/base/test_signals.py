"""A job stops once (yade_mss.base.stopOnce): a second SIGINT or SIGTERM during the first one's clean-up (a
terminal's Ctrl-C and the mss launcher's forwarded copy arrive together) must not cut the clean-up short."""
import os
import signal
import subprocess
import sys
import tempfile
import unittest

SCRIPT = r'''
import sys, time
from yade_mss.base import exitStatus, stopOnce
seen = []
stopOnce(seen=seen)
try:
    print('ready', flush=True)
    time.sleep(60)
except KeyboardInterrupt:
    print('cleaning', flush=True)
    time.sleep(1.0)  # the second signal arrives here
    print('cleaned', flush=True)
    sys.exit(exitStatus(seen))
'''


class StopOnce(unittest.TestCase):
    def stop(self, first, second):
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, 'job.py')
            with open(path, 'w') as f:
                f.write(SCRIPT)
            p = subprocess.Popen([sys.executable, path], stdout=subprocess.PIPE, text=True)
            self.assertEqual(p.stdout.readline().strip(), 'ready')
            p.send_signal(first)
            self.assertEqual(p.stdout.readline().strip(), 'cleaning')
            p.send_signal(second)
            out = p.stdout.read()
            p.wait(timeout=30)
            self.assertIn('cleaned', out)
            return p.returncode

    def test_a_second_signal_waits_for_the_clean_up(self):
        self.assertEqual(self.stop(signal.SIGINT, signal.SIGINT), 130)
        self.assertEqual(self.stop(signal.SIGTERM, signal.SIGINT), 143)
        self.assertEqual(self.stop(signal.SIGINT, signal.SIGTERM), 130)

    def test_off_the_main_thread_nothing_is_installed(self):
        import threading
        from yade_mss.base import stopOnce
        got = []
        t = threading.Thread(target=lambda: got.append(stopOnce()))
        t.start()
        t.join()
        self.assertEqual(got, [{}])
        self.assertIs(signal.getsignal(signal.SIGINT), signal.default_int_handler)

    def test_restored(self):
        from yade_mss.base import restoreSignals, stopOnce
        before = stopOnce()
        self.assertTrue(getattr(signal.getsignal(signal.SIGINT), 'mssStopOnce', False))
        self.assertEqual(stopOnce(), {})  # one is installed: a library call inside a command installs none
        restoreSignals(before)
        self.assertIs(signal.getsignal(signal.SIGINT), signal.default_int_handler)
        self.assertEqual(signal.getsignal(signal.SIGTERM), signal.SIG_DFL)


if __name__ == '__main__':
    unittest.main()


class SlowPhase(unittest.TestCase):
    """No wait over a second is silent (the bug: 141 s without a word after a batch's last grain), and a quick
    phase prints nothing."""

    def test_a_slow_phase_says_so_a_quick_one_does_not(self):
        import contextlib
        import io
        import time
        from yade_mss.base import slowPhase
        out = io.StringIO()
        with contextlib.redirect_stdout(out):
            with slowPhase('quick', after=0.5):
                pass
            with slowPhase('disabled', enabled=False, after=0.05):
                time.sleep(0.2)
            with slowPhase('slow', after=0.1):
                time.sleep(0.4)
        lines = out.getvalue().splitlines()
        self.assertEqual(lines[0], 'slow ...')
        self.assertRegex(lines[1], r'^slow: done in [0-9]+\.[0-9] s$')
        self.assertEqual(len(lines), 2)
