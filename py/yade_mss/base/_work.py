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


def checkSweep(where, first, firstCount, counts, maxWork, lighter):
    """A sweep's estimate: its first, cheapest step took *first* seconds for *firstCount* spheres; each count of
    *counts* is one more step, costing as the core's model scales. Refused past *maxWork*; returns the seconds."""
    seconds = sum(first * _scale(n) / _scale(firstCount) for n in counts)
    what = '%d generations of %d to %d spheres (the first took %.3g s)' % (
        len(counts), min(counts), max(counts), first) if counts else 'nothing'
    check(where, what, seconds, maxWork, lighter)
    return seconds


def bar(total, where, seconds):
    """A progress bar (tqdm, on standard error) for *total* steps, shown where they should take over 2 s."""
    from tqdm import tqdm
    return tqdm(total=total, desc=where, file=sys.stderr, leave=False, disable=seconds < 2.0)
