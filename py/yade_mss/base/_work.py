"""Heavy requests on the Python side: the core's work limit (pkg/mss/work.hpp) applied to sweeps of many
generations (curve, ochart, spheropolygons), and their progress bars."""

import math
import sys

from .. import _mss


def check(where, what, seconds, maxWork, lighter):
    """Refuses (ValueError, the core's message) *seconds* of estimated work over *maxWork*."""
    _mss.checkWork(where, what, float(seconds), float(maxWork), lighter)


def _scale(n):
    # the core's model of a generation's cost against its sphere count (pkg/mss/generation/estimates.cpp)
    return 1.0 + 0.5 * math.log1p(n)


def checkSweep(where, first, firstCount, counts, maxWork, lighter, measured=()):
    """A sweep's estimate: its first, cheapest step took *first* seconds for *firstCount* spheres; each count of
    *counts* is one more step, costing as the core's model scales. Where more steps were run first
    (*measured*: (count, seconds) pairs, the dearest among them), a step costs what the broken line through
    them all says on log-log axes: a step's scoring grows with its spheres, far faster than the generation
    the model scales (the model alone said under 600 s of a 1:65535 curve that ran past 400 s at 60 %).
    Refused past *maxWork*; returns the seconds."""
    known = sorted(set([(firstCount, first)] + [(c, t) for c, t in measured if c > 0 and t > 0]))
    if len(known) > 1 and first > 0 and firstCount > 0:
        import numpy as np
        x, y = np.log([c for c, _ in known]), np.log([t for _, t in known])
        # x 1.25: the cost bends down as it nears the cap, so the chords lie under it (measured: a 20-point
        # 1:65535 curve's chords said 20.8 s of the 24 s it took)
        seconds = 1.25 * float(np.sum(np.exp(np.interp(np.log(np.maximum(list(counts) or [1], 1)), x, y)))) \
            if counts else 0.0
    else:
        seconds = sum(first * _scale(n) / _scale(firstCount) for n in counts)
    what = '%d generations of %d to %d spheres (the first took %.3g s)' % (
        len(counts), min(counts), max(counts), first) if counts else 'nothing'
    check(where, what, seconds, maxWork, lighter)
    return seconds


def bar(total, where, seconds):
    """A progress bar (tqdm, on standard error) for *total* steps, shown where they should take over 2 s."""
    from tqdm import tqdm
    return tqdm(total=total, desc=where, file=sys.stderr, leave=False, disable=seconds < 2.0)


class slowPhase(object):
    """``with slowPhase('batch: writing the assembly', enabled):`` says what a phase is doing once it has run
    for *after* seconds (then, when it ends, how long it took), so that no wait over a second is silent, while
    a quick phase prints nothing (the console shown in the manual stays as it is)."""

    def __init__(self, text, enabled=True, after=1.0):
        self.text, self.enabled, self.after, self.timer, self.said = text, enabled, after, None, False

    def _say(self):
        self.said = True
        print('%s ...' % self.text, flush=True)

    def __enter__(self):
        import threading
        import time
        self.t0 = time.perf_counter()
        if self.enabled:
            self.timer = threading.Timer(self.after, self._say)
            self.timer.daemon = True
            self.timer.start()
        return self

    def __exit__(self, *exc):
        import time
        if self.timer is not None:
            self.timer.cancel()
            self.timer.join()
        if self.said and exc[0] is None:
            print('%s: done in %.1f s' % (self.text, time.perf_counter() - self.t0), flush=True)
        return False
