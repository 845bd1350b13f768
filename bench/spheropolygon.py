"""Spheropolygons on the cow-like silhouette (420 x 300 pixels: body, head, four legs, a thin tail), N = 30:
each initialisation at r = 2 pixels (Algorithm 1 alone, then with relocations), the default (r chosen by least error), the time per fit and per iteration,
and the error checked by an independent rasteriser. Run: PYTHONPATH=build/py /usr/bin/python3 bench/spheropolygon.py"""
import time

from yade_mss import spheropolygon
from yade_mss._spheropolygon import cow, rasterizeNumpy

c = cow()
print('cow: %d x %d pixels, %d particle pixels; load %s' % (c.shape + (c.sum(), open('/proc/loadavg').read().split()[0])))
print('%-22s %8s %8s %6s %8s %10s' % ('run', 'error %', 'pixels', 'iter.', 'seconds', 's / iter.'))
for init in ('circle', 'boundary', 'curvature'):
    t = time.perf_counter()
    r = spheropolygon(c, 30, radius=2.0, init=init, relocations=0)  # the paper's Algorithm 1 alone
    s = time.perf_counter() - t
    print('%-22s %8.2f %8d %6d %8.2f %10.3f' % ('%s, r = 2' % init, 100 * r['error'], r['errorPixels'],
                                                r['iterations'], s, s / max(1, r['iterations'])))
for init in ('boundary', 'curvature'):
    t = time.perf_counter()
    r = spheropolygon(c, 30, radius=2.0, init=init)  # with the relocations (default 10)
    s = time.perf_counter() - t
    print('%-22s %8.2f %8d %6d %8.2f %10.3f' % ('%s, r = 2, reloc.' % init, 100 * r['error'], r['errorPixels'],
                                                r['iterations'], s, s / max(1, r['iterations'])))
t = time.perf_counter()
r = spheropolygon(c, 30)
s = time.perf_counter() - t
independent = int((rasterizeNumpy(r['vertices'], r['spheroradius'], c.shape) != c).sum())
print('%-22s %8.2f %8d %6d %8.2f   (r = %.3g chosen; independent rasteriser: %d error pixels)'
      % ('default (auto)', 100 * r['error'], r['errorPixels'], r['iterations'], s, r['spheroradius'], independent))
