"""Strict keyword checks for the functions that pass options through (mssClump and friends)."""

import difflib


def split(func, kw, *groups, **how):
    """Sorts the keywords *kw* of *func* into one dict per group of valid names (tuples), in order.

    An unknown keyword raises TypeError naming it and the closest valid one, before any work is done (Python's
    own message for a function without ``**kw``, plus the suggestion). *extra* (a keyword of split) names the
    function's own parameters, so that a misspelt one ('orientaton') is suggested and listed too.
    """
    extra = tuple(how.pop('extra', ()))
    if how:
        raise TypeError('split: unexpected %s' % ', '.join(sorted(how)))
    out = [{} for _ in groups]
    for key, value in kw.items():
        for i, names in enumerate(groups):
            if key in names:
                out[i][key] = value
                break
        else:
            allowed = sorted(set(n for names in groups + (extra,) for n in names))
            lower = {n.lower(): n for n in allowed}
            near = difflib.get_close_matches(key.lower(), list(lower), n=1, cutoff=0.6)
            hint = ": did you mean '%s'?" % lower[near[0]] if near else ' (valid: %s)' % ', '.join(allowed)
            raise TypeError("%s() got an unexpected keyword argument '%s'%s" % (func, key, hint))
    return out
