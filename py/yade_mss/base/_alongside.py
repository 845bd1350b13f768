"""Work done in a forked child while the caller goes on: a batch's last files written on the core its workers
have just left, instead of one after another on one core."""

import gc
import os
import signal
import sys
import threading
import time

MESSAGE_BYTES = 1 << 12  # the child's error, as much of it as is said: under a pipe's buffer, written at once
STOP_SECONDS = 5.0  # a stopped child is waited for this long before it is killed
_RAISED = {'ValueError': ValueError, 'TypeError': TypeError, 'RuntimeError': RuntimeError}


def canFork():
    """Whether a child forked now could run Python safely: os.fork exists, this is the main thread, outside YADE
    (its own threads run C++), and every other thread is a daemon (a progress timer, a sampler: a non-daemon
    thread is the caller's own work, and a lock it held at the fork would stay held in the child)."""
    return (hasattr(os, 'fork') and threading.current_thread() is threading.main_thread()
            and 'yade' not in sys.modules
            and all(t.daemon or t is threading.main_thread() for t in threading.enumerate()))


class alongside(object):
    """``with alongside(job, where): ...`` runs ``job()`` in a forked child while the block runs in the caller.

    Leaving the block waits for the child and raises its error in the caller (ValueError, TypeError or
    RuntimeError with the child's message; another exception as RuntimeError naming its type). If the block
    raises (a Ctrl-C included), the child is stopped (SIGTERM, which it turns into KeyboardInterrupt: its
    temporary files are removed), reaped, and the block's exception goes on. Where no child can be forked safely
    (:func:`canFork`), or the fork fails, ``job()`` runs in the caller on entering the block.

    The child leaves with ``os._exit``: never through the caller's ``finally`` clauses, exit handlers or
    buffered output. *job* must not use OpenMP (libgomp's threads are not there after a fork).
    """

    def __init__(self, job, where):
        self.job, self.where, self.pid, self.pipe = job, where, None, None

    def __enter__(self):
        if not canFork():
            self.job()
            return self
        stops = (signal.SIGINT, signal.SIGTERM)
        r, w = os.pipe()
        # a stop is held off across the fork: the child must be in its own try before one can reach it
        mask = signal.pthread_sigmask(signal.SIG_BLOCK, stops)
        gc.freeze()  # the child's collections do not touch the caller's objects: their pages stay shared
        try:
            pid = os.fork()
        except BaseException as e:
            gc.unfreeze()
            signal.pthread_sigmask(signal.SIG_SETMASK, mask)
            os.close(r)
            os.close(w)
            if not isinstance(e, OSError):
                raise
            self.job()  # no process to spare (EAGAIN, ENOMEM): the work is done here, as without a fork
            return self
        if pid == 0:
            self._child(r, w, mask, stops)
        self.pid, self.pipe = pid, r
        try:
            os.close(w)
            gc.unfreeze()
            signal.pthread_sigmask(signal.SIG_SETMASK, mask)  # a stop held off is raised here: the child stopped
        except BaseException:
            self._stop()
            raise
        return self

    def _child(self, r, w, mask, stops):
        code = 1
        try:
            try:
                os.close(r)

                def once(signum, frame):  # one KeyboardInterrupt at most: the exit below is never cut short
                    for s in stops:
                        signal.signal(s, signal.SIG_IGN)
                    raise KeyboardInterrupt
                for s in stops:
                    signal.signal(s, once)
                signal.pthread_sigmask(signal.SIG_SETMASK, mask)
                self.job()
                code = 0
            except BaseException as e:  # noqa: BLE001 (said to the caller, which raises it)
                text = '%s\0%s' % (type(e).__name__, e)
                os.write(w, text.encode('utf-8', 'backslashreplace')[:MESSAGE_BYTES])
        finally:
            os._exit(code)

    def _stop(self):
        """Stops the child (if it still runs) and reaps it."""
        if self.pid is None:
            return
        pid, self.pid = self.pid, None
        self._closePipe()
        try:
            os.kill(pid, signal.SIGTERM)
        except ProcessLookupError:
            pass
        end = time.monotonic() + STOP_SECONDS
        while os.waitpid(pid, os.WNOHANG) == (0, 0):
            if time.monotonic() > end:
                os.kill(pid, signal.SIGKILL)
                os.waitpid(pid, 0)
                return
            time.sleep(0.01)

    def _closePipe(self):
        if self.pipe is not None:
            os.close(self.pipe)
            self.pipe = None

    def __exit__(self, kind, error, trace):
        if self.pid is None:
            return False
        if kind is not None:
            self._stop()
            return False
        try:
            parts = []
            while sum(len(p) for p in parts) < MESSAGE_BYTES:
                part = os.read(self.pipe, MESSAGE_BYTES)
                if not part:
                    break
                parts.append(part)
            _, status = os.waitpid(self.pid, 0)
        except BaseException:
            self._stop()
            raise
        self.pid = None
        self._closePipe()
        if status == 0:
            return False
        text = b''.join(parts)[:MESSAGE_BYTES].decode('utf-8', 'backslashreplace')
        if '\0' in text:
            name, message = text.split('\0', 1)
            if name == 'KeyboardInterrupt':
                raise RuntimeError('%s: the process that wrote it was stopped (SIGINT or SIGTERM)' % self.where)
            raise _RAISED.get(name, RuntimeError)(message if name in _RAISED else '%s: %s' % (name, message))
        how = ('killed by signal %d' % os.WTERMSIG(status) if os.WIFSIGNALED(status)
               else 'exit status %d' % os.waitstatus_to_exitcode(status))
        raise RuntimeError('%s: the process that wrote it ended without a word (%s)' % (self.where, how))

