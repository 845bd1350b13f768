"""A job stops once: the first SIGINT or SIGTERM raises KeyboardInterrupt, the later ones wait.

A terminal's Ctrl-C reaches every process of the group at once, and the ``mss`` launcher passes on a SIGINT or
SIGTERM sent to it alone; so a command's Python often gets the same stop twice, a few microseconds apart. A
second KeyboardInterrupt inside the first one's clean-up would cut short the wait for workers and the writing of
what was done: nothing half-published needs the clean-up to run whole."""

import signal
import threading


def stopOnce(signals=(signal.SIGINT, signal.SIGTERM), seen=None):
    """Installs a handler on each of *signals* (main thread only: elsewhere Python keeps its own) that records
    the signal in the list *seen*, ignores every one of *signals* from then on and raises KeyboardInterrupt.

    :return: the handlers it replaced, {signal: handler}, for :func:`restore`; {} off the main thread or when
        such a handler is installed already (a command's, around a library call that would install its own)
    """
    if threading.current_thread() is not threading.main_thread():
        return {}
    if any(getattr(signal.getsignal(s), 'mssStopOnce', False) for s in signals):
        return {}
    before = {s: signal.getsignal(s) for s in signals}

    def once(signum, frame):
        for s in signals:
            signal.signal(s, signal.SIG_IGN)
        if seen is not None:
            seen.append(signum)
        raise KeyboardInterrupt
    once.mssStopOnce = True
    for s in signals:
        signal.signal(s, once)
    return before


def restore(before):
    """Puts back the handlers :func:`stopOnce` replaced."""
    for s, h in before.items():
        signal.signal(s, h if h is not None else signal.SIG_DFL)


def exitStatus(seen):
    """A stopped command's exit status: 128 + the signal that stopped it (130 for Ctrl-C, 143 for SIGTERM)."""
    return 128 + int(seen[0] if seen else signal.SIGINT)
