"""Where a batch's grains run: in this process, in local worker processes (one OpenMP thread each, a pipe
each, dying with the batch), or as tasks on a Dask cluster. Results do not depend on which ran what: generation
is deterministic, one thread per grain. The grain's own work comes in as functions (``runOne``, ``runMany``)
and so does the row of a grain whose worker died (``failed``), so that this module knows nothing of grains.
"""

import itertools
import os
import signal

from .. import _mss

WORKER_DIED = ('a worker process died', 'every worker process died')  # how a dead worker's rows begin
AHEAD_CHUNKS = 4  # Dask: chunks of grains submitted ahead per worker thread


def freeCores():
    """The cores not busy with other processes now (the load over the last minute; at least one): on a loaded
    machine one worker beat two."""
    n = os.cpu_count() or 1
    try:
        busy = int(os.getloadavg()[0] + 0.5)
    except OSError:
        busy = 0
    return max(1, n - busy)


def _oneThread():
    """A local worker's start: one OpenMP thread, and death with the batch (Linux's PR_SET_PDEATHSIG), so that a
    killed batch leaves no worker computing."""
    try:
        import ctypes
        ctypes.CDLL(None, use_errno=True).prctl(1, int(signal.SIGTERM))  # PR_SET_PDEATHSIG = 1
    except (OSError, AttributeError):
        pass
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is the batch's to handle: it stops the workers
    # the batch's own SIGTERM handler (a KeyboardInterrupt, the command line's) came with the fork: the pool's
    # shutdown terminates its workers, which printed that interrupt's traceback; a worker just ends
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    _mss.setOmpThreads(1)


def clusterSecurity(security=None, caFile=None, cert=None, key=None):
    """Dask's TLS settings for a scheduler: a ``distributed.Security`` as given, or one from the CA, certificate
    and key files, or None (then Dask's configuration decides, ``distributed.comm.tls.*``)."""
    if security is not None:
        if caFile or cert or key:
            raise ValueError('batch: give security or the TLS files, not both')
        return security
    if not (caFile or cert or key):
        return None
    if not (caFile and cert and key):
        raise ValueError('batch: TLS needs the CA file, the certificate and the key (--tls-ca-file, --tls-cert, '
                         '--tls-key)')
    for f in (caFile, cert, key):
        if not os.path.isfile(f):
            raise ValueError('batch: %s: no such file (TLS)' % f)
    from distributed.security import Security
    return Security(tls_ca_file=caFile, tls_client_cert=cert, tls_client_key=key, require_encryption=True)


def checkScheduler(where, scheduler, security=None):
    """Before any work: a Dask scheduler's address is SCHEME://HOST:PORT (tcp, tls, ws, wss; no spaces or control
    characters, a port in 1..65535), and a tls:// one comes with TLS (the files, a Security, or Dask's own
    configuration): Dask's own errors for these were a traceback or "invalid literal for int()"."""
    if security is not None and not isinstance(security, bool):
        from distributed.security import Security
        if not isinstance(security, Security):
            raise TypeError('%s: security must be a distributed.Security (or True: Dask\'s temporary credentials), '
                            'got %r' % (where, security))
    if scheduler is None:
        return None
    from urllib.parse import urlsplit
    if not isinstance(scheduler, str):
        raise TypeError('%s: the scheduler is an address SCHEME://HOST:PORT, got %r' % (where, scheduler))
    try:
        u = urlsplit(scheduler)
        port = u.port
    except ValueError:
        port = None
    if not scheduler.isprintable() or ' ' in scheduler or u.scheme not in ('tcp', 'tls', 'ws', 'wss') or not u.hostname \
            or port is None or not 1 <= port <= 65535 or u.path not in ('', '/'):
        raise ValueError('%s: the scheduler address must be SCHEME://HOST:PORT (scheme tcp, tls, ws or wss, a '
                         'port in 1..65535, no spaces or control characters), got %r' % (where, scheduler))
    if u.scheme == 'tls' and security is None:
        import dask
        if not dask.config.get('distributed.comm.tls.ca-file', None):
            raise ValueError('%s: a tls:// scheduler needs TLS: the CA file, certificate and key (--tls-ca-file, '
                             '--tls-cert, --tls-key; security= in Python) or Dask\'s configuration '
                             '(distributed.comm.tls.*)' % where)
    return scheduler


def executor(workers, scheduler, runOne, runMany, failed, security=None, connectTimeout=5.0, tasks=None):
    """(submit-all function yielding results as they finish, closer): *runOne* (a task) runs a grain,
    *runMany* (a list of tasks) several, as Dask's tasks; *failed* (task, message) is the row of a grain whose
    worker died. *tasks*: the list the submit function will be given, known now: local workers are forked with
    it and get each task's place in it, not the task (a grain's crop is cut in its worker, not sent)."""
    if scheduler:
        try:
            from distributed import Client, as_completed
        except ImportError:
            raise RuntimeError('batch: --scheduler needs Dask (Debian: python3-distributed)')
        if security is not None and not str(scheduler).startswith('tls://'):
            raise ValueError('batch: with TLS the scheduler address is tls://HOST:PORT, got %s' % scheduler)
        try:
            client = Client(scheduler, timeout=connectTimeout, security=security)
        except (OSError, TimeoutError) as e:  # asyncio's and Dask's time-outs are both
            raise RuntimeError('batch: the Dask scheduler at %s did not answer within %g s (--connect-timeout, '
                               'connectTimeout): is it running and reachable? (%s: %s)'
                               % (scheduler, connectTimeout, type(e).__name__, e))

        def run(tasks):
            # a few grains per task: Dask's per-task cost (~ms) stays small against the grains' own; still
            # several tasks per worker, so that a lost worker costs little and the load stays even
            slots = max(1, sum(client.nthreads().values()))
            size = max(1, min(16, len(tasks) // (8 * slots)))
            chunks = (tasks[i:i + size] for i in range(0, len(tasks), size))
            # submitted a few ahead of the workers, not all at once: each chunk's crops are cut and packed here as
            # it is sent, and the whole list at once kept the workers waiting (2.9 s of 10^4 grains' 37 s)
            done = as_completed()
            for chunk in itertools.islice(chunks, AHEAD_CHUNKS * slots):
                done.add(client.submit(runMany, chunk, pure=False, retries=3))
            for fut in done:
                chunk = next(chunks, None)
                if chunk is not None:
                    done.add(client.submit(runMany, chunk, pure=False, retries=3))
                for result in fut.result():
                    yield result
        return run, client.close
    if workers == 1:
        return (lambda tasks: (runOne(t) for t in tasks)), (lambda: None)
    pool = _LocalPool(workers, runOne, failed, tasks)
    return pool.run, pool.close


def _workerLoop(conn, runOne, tasks=None):
    """A local worker: grains in (or their places in *tasks*, the list it was forked with), rows and results
    out, over its own pipe, until it gets None."""
    _oneThread()
    while True:
        try:
            task = conn.recv()
        except (EOFError, OSError):
            return
        if task is None:
            return
        conn.send(runOne(tasks[task] if tasks is not None else task))


class _LocalPool(object):
    """Worker processes, each with a pipe of its own (not concurrent.futures' shared result queue: a worker
    killed while it wrote there left a part of a message that blocked every reader, and the batch hung). A
    worker that dies fails the grains it had; the others go on; the batch always ends. Forked: a user's script
    needs no __main__ guard (spawn would import it again in every child); each child runs on one OpenMP thread
    (GNU OpenMP hangs in a forked child that asks for the parent's thread pool).

    Each worker has AHEAD grains in flight: the next is in its pipe while the batch stores the last one's
    result, so that a worker never waits for the batch (with one in flight, two workers on 2 cores took 35 s
    over 10^4 grains of a scan, 24.5 s with two)."""

    AHEAD = 2

    def __init__(self, n, runOne, failed, tasks=None):
        self.failed, self.tasks = failed, tasks
        import multiprocessing
        ctx = multiprocessing.get_context('fork')
        self.workers = []
        for _ in range(n):
            mine, theirs = ctx.Pipe(duplex=True)
            proc = ctx.Process(target=_workerLoop, args=(theirs, runOne, tasks), daemon=True)
            proc.start()
            theirs.close()  # only the child holds its end: its death is EOF here
            self.workers.append([proc, mine, []])  # process, pipe, the grains it has (oldest first)

    def run(self, tasks):
        import select
        from collections import deque
        known = self.tasks is not None
        if known and tasks is not self.tasks:
            raise ValueError('_LocalPool.run: its workers were forked with another list of tasks')
        # places in the list where the workers have it (a grain's crop is cut there, not here), else the tasks
        todo = deque(range(len(tasks))) if known else deque(tasks)
        task = tasks.__getitem__ if known else (lambda t: t)
        live = list(self.workers)
        # one poll set for the run, each worker's pipe and death (its sentinel) in it: multiprocessing's wait()
        # made and filled a selector a grain
        poller, owner = select.poll(), {}
        for x, w in enumerate(live):
            for fd in (w[1].fileno(), w[0].sentinel):
                poller.register(fd, select.POLLIN)
                owner[fd] = x

        def give(w):
            while todo and len(w[2]) < self.AHEAD:
                w[2].append(todo.popleft())
                try:
                    w[1].send(w[2][-1])
                except (OSError, ValueError):
                    return  # dead already: its sentinel says so
        for w in live:
            give(w)
        while any(w[2] for w in live):
            events = poller.poll()
            piped = {owner[fd] for fd, _ in events if fd == self.workers[owner[fd]][1].fileno()}
            for x in sorted({owner[fd] for fd, _ in events}):
                w = self.workers[x]
                if w not in live:
                    continue
                try:
                    result = w[1].recv() if w[1].poll() else None
                except (EOFError, OSError):
                    result = None
                if result is None and w[0].is_alive() and x not in piped:
                    continue
                if result is None:  # killed (or out of memory) before its grains were done
                    live.remove(w)
                    for fd in (w[1].fileno(), w[0].sentinel):
                        poller.unregister(fd)
                    lost, w[2] = w[2], []
                    for t in lost:
                        yield self.failed(task(t), WORKER_DIED[0] + ' (killed, or out of memory) before this '
                                          'grain was done; run the batch again to retry it')
                    if not live:  # nobody left: the rest fail too, the batch ends
                        while todo:
                            yield self.failed(task(todo.popleft()), WORKER_DIED[1] + '; run the batch again')
                    continue
                w[2].pop(0)
                give(w)  # before the result is stored: the worker goes on meanwhile
                yield result

    def close(self):
        """At once: a grain being computed is lost, every finished one is already written."""
        for proc, conn, task in self.workers:
            if proc.is_alive():
                proc.terminate()
        for proc, conn, task in self.workers:
            proc.join(timeout=5)
            conn.close()
