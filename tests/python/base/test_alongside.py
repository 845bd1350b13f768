"""Work in a forked child alongside the caller (yade_mss.base.alongside): the child's errors reach the caller with
their messages, a child is never left running or unreaped, a stopped child leaves no temporary file, and where a
fork is not safe the work runs in the caller."""
import os
import signal
import subprocess
import sys
import tempfile
import threading
import time
import unittest

from yade_mss.base import alongside, atomicWrite, canFork


def _waitFor(path, seconds=60.0):
    end = time.monotonic() + seconds
    while not os.path.exists(path):
        if time.monotonic() > end:
            raise AssertionError('%s never appeared' % path)
        time.sleep(0.01)


def _gone(pid):
    """Whether the process *pid* is gone and reaped (a zombie still has its /proc entry)."""
    return not os.path.exists('/proc/%d' % pid)


class Alongside(unittest.TestCase):
    def test_the_job_runs_in_another_process_while_the_block_runs(self):
        with tempfile.TemporaryDirectory() as d:
            mine, theirs = os.path.join(d, 'mine'), os.path.join(d, 'theirs')

            def job():
                _waitFor(mine)  # the block's file is there before the job ends: they ran at the same time
                atomicWrite(theirs, None, 'test', str(os.getpid()).encode())
            self.assertTrue(canFork())
            with alongside(job, 'test: theirs'):
                atomicWrite(mine, None, 'test', b'1')
            with open(theirs) as f:
                pid = int(f.read())
            self.assertNotEqual(pid, os.getpid())
            self.assertTrue(_gone(pid))
            self.assertEqual(sorted(os.listdir(d)), ['mine', 'theirs'])

    def test_the_childs_error_is_raised_here_with_its_message(self):
        def fails(kind, text):
            def job():
                raise kind(text)
            return job
        for kind in (ValueError, TypeError, RuntimeError):
            with self.assertRaises(kind) as e:
                with alongside(fails(kind, 'batch: x.vtk: cannot write (No space left on device)'), 'test'):
                    pass
            self.assertEqual(str(e.exception), 'batch: x.vtk: cannot write (No space left on device)')
        with self.assertRaises(RuntimeError) as e:
            with alongside(fails(KeyError, 'label_3'), 'test'):
                pass
        self.assertEqual(str(e.exception), "KeyError: 'label_3'")

    def test_a_child_that_dies_is_an_error_that_says_how(self):
        with self.assertRaises(RuntimeError) as e:
            with alongside(lambda: os.kill(os.getpid(), signal.SIGKILL), 'batch: report.html'):
                pass
        self.assertIn('batch: report.html: the process that wrote it ended without a word (killed by signal 9)',
                      str(e.exception))

    def test_an_error_in_the_block_stops_the_child_which_leaves_no_temporary_file(self):
        with tempfile.TemporaryDirectory() as d:
            started, pidFile = os.path.join(d, 'started'), os.path.join(d, 'pid')

            def slow(tmp):
                with open(pidFile, 'w') as f:
                    f.write(str(os.getpid()))
                open(started, 'w').close()
                time.sleep(120)  # stopped here, inside the atomic write

            def job():
                atomicWrite(os.path.join(d, 'report.html'), slow, 'test')
            with self.assertRaises(ValueError) as e:
                with alongside(job, 'test'):
                    _waitFor(started)
                    raise ValueError('the block failed')
            self.assertEqual(str(e.exception), 'the block failed')  # the block's error, not the child's
            with open(pidFile) as f:
                self.assertTrue(_gone(int(f.read())))
            self.assertEqual(sorted(os.listdir(d)), ['pid', 'started'])  # no .report.html.*.html left

    def test_a_child_stopped_from_outside_is_an_error_not_a_success(self):
        with tempfile.TemporaryDirectory() as d:
            pidFile = os.path.join(d, 'pid')

            def job():
                with open(pidFile, 'w') as f:
                    f.write(str(os.getpid()))
                time.sleep(120)
            with self.assertRaises(RuntimeError) as e:
                with alongside(job, 'batch: report.html'):
                    _waitFor(pidFile)  # written inside the job: the child's own handler is in place
                    with open(pidFile) as f:
                        os.kill(int(f.read()), signal.SIGTERM)
            self.assertEqual(str(e.exception), 'batch: report.html: the process that wrote it was stopped (SIGINT '
                                               'or SIGTERM)')

    def test_with_a_thread_of_the_callers_own_running_the_job_runs_here(self):
        stop = threading.Event()
        t = threading.Thread(target=stop.wait)  # not a daemon: the caller's own work
        t.start()
        try:
            self.assertFalse(canFork())
            ran = []
            with alongside(lambda: ran.append(os.getpid()), 'test'):
                self.assertEqual(ran, [os.getpid()])  # before the block, in this process
        finally:
            stop.set()
            t.join()
        self.assertTrue(canFork())

    def test_a_fork_that_fails_does_the_work_here(self):
        real = os.fork

        def refused():
            raise BlockingIOError(11, 'Resource temporarily unavailable')
        ran = []
        os.fork = refused
        try:
            with alongside(lambda: ran.append(os.getpid()), 'test'):
                self.assertEqual(ran, [os.getpid()])
        finally:
            os.fork = real

    def test_ctrl_c_to_the_whole_group_stops_both_and_leaves_nothing(self):
        """A terminal's Ctrl-C reaches the batch and its child at once: the command ends with 130, the child is
        reaped, and neither leaves a temporary file."""
        script = r'''
import os, sys, time
from yade_mss.base import alongside, atomicWrite, exitStatus, stopOnce
d = sys.argv[1]
seen = []
stopOnce(seen=seen)
def slow(tmp):
    os.write(1, b'child %d\n' % os.getpid())  # one write each: the two lines never interleave
    time.sleep(120)
try:
    with alongside(lambda: atomicWrite(os.path.join(d, 'report.html'), slow, 'batch'), 'batch'):
        atomicWrite(os.path.join(d, 'assembly.txt'), lambda tmp: (os.write(1, b'parent\n'), time.sleep(120)),
                    'batch')
except KeyboardInterrupt:
    sys.exit(exitStatus(seen))
'''
        with tempfile.TemporaryDirectory() as d:
            p = subprocess.Popen([sys.executable, '-c', script, d], stdout=subprocess.PIPE, text=True,
                                 start_new_session=True)
            with p.stdout:
                lines = sorted(p.stdout.readline().strip() for _ in range(2))
            self.assertEqual(lines[1], 'parent')
            child = int(lines[0].split()[1])
            os.killpg(p.pid, signal.SIGINT)
            self.assertEqual(p.wait(timeout=60), 130)
            self.assertTrue(_gone(child))
            self.assertEqual(os.listdir(d), [])



if __name__ == '__main__':
    unittest.main()
