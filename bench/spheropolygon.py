"""Spheropolygons on the cow-like silhouette (420 x 300 pixels: body, head, four legs, a thin tail), N = 30:
each initialisation at r = 2 pixels (Algorithm 1 alone, then with relocations), the default (r chosen by least error), the time per fit and per iteration,
and the error checked by an independent rasteriser. Appends a row a run to bench/results/spheropolygon.csv.
Run: PYTHONPATH=build/py /usr/bin/python3 bench/spheropolygon.py"""
import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from batch_scale import appendRows  # noqa: E402

from yade_mss import spheropolygon  # noqa: E402
from yade_mss.spheropolygons import cow, rasterizeNumpy  # noqa: E402

c = cow()
rows = []  # (run, error %, error pixels, iterations, seconds, spheroradius)
print('cow: %d x %d pixels, %d particle pixels; load %s' % (c.shape + (c.sum(), open('/proc/loadavg').read().split()[0])))
print('%-22s %8s %8s %6s %8s %10s' % ('run', 'error %', 'pixels', 'iter.', 'seconds', 's / iter.'))
for init in ('circle', 'boundary', 'curvature'):
    t = time.perf_counter()
    r = spheropolygon(c, 30, radius=2.0, init=init, relocations=0)  # the paper's Algorithm 1 alone
    s = time.perf_counter() - t
    print('%-22s %8.2f %8d %6d %8.2f %10.3f' % ('%s, r = 2' % init, 100 * r['error'], r['errorPixels'],
                                                r['iterations'], s, s / max(1, r['iterations'])))
    rows.append(('%s, r = 2' % init, 100 * r['error'], r['errorPixels'], r['iterations'], s, r['spheroradius']))
for init in ('boundary', 'curvature'):
    t = time.perf_counter()
    r = spheropolygon(c, 30, radius=2.0, init=init)  # with the relocations (default 10)
    s = time.perf_counter() - t
    print('%-22s %8.2f %8d %6d %8.2f %10.3f' % ('%s, r = 2, reloc.' % init, 100 * r['error'], r['errorPixels'],
                                                r['iterations'], s, s / max(1, r['iterations'])))
    rows.append(('%s, r = 2, reloc.' % init, 100 * r['error'], r['errorPixels'], r['iterations'], s,
                 r['spheroradius']))
t = time.perf_counter()
r = spheropolygon(c, 30)
s = time.perf_counter() - t
independent = int((rasterizeNumpy(r['vertices'], r['spheroradius'], c.shape) != c).sum())
print('%-22s %8.2f %8d %6d %8.2f   (r = %.3g chosen; independent rasteriser: %d error pixels)'
      % ('default (auto)', 100 * r['error'], r['errorPixels'], r['iterations'], s, r['spheroradius'], independent))
assert independent == r['errorPixels'], (independent, r['errorPixels'])
rows.append(('default (auto)', 100 * r['error'], r['errorPixels'], r['iterations'], s, r['spheroradius']))

# beyond the paper (its sections 4-5): a radius per vertex (none below the spheroradius, or below half of it), and
# a vertex in every convex or concave region turning by >= 90 degrees; at r = 2 px from the boundary start
print('%-34s %8s %8s %8s %8s' % ('beyond the paper, r = 2 px', 'error %', 'pixels', 'radii', 'seconds'))
for label, kw in (('one radius (relocations)', {}),
                  ('radius per vertex, min r', dict(vertexRadii=True)),
                  ('radius per vertex, min r / 2', dict(vertexRadii=True, minRadius=1.0)),
                  ('a vertex in every region', dict(regionVertices=True)),
                  ('both, min r / 2', dict(vertexRadii=True, minRadius=1.0, regionVertices=True))):
    t = time.perf_counter()
    r = spheropolygon(c, 30, radius=2.0, init='boundary', **kw)
    s = time.perf_counter() - t
    radii = r.get('radii', [r['spheroradius']])
    independent = int((rasterizeNumpy(r['vertices'], radii if 'radii' in r else r['spheroradius'], c.shape) != c).sum())
    assert independent == r['errorPixels'], (independent, r['errorPixels'])
    extra = '  regions %d, %d filled, %d empty' % (r['regions'], r['regionsFilled'], r['regionsMissed']) \
        if 'regions' in r else ''
    print('%-34s %8.2f %8d %8s %8.2f%s' % (label, 100 * r['error'], r['errorPixels'],
                                           '%.2g-%.2g' % (min(radii), max(radii)), s, extra))
    rows.append((label, 100 * r['error'], r['errorPixels'], r['iterations'], s, float(min(radii))))

appendRows('spheropolygon.csv', ['run', 'error_percent', 'error_pixels', 'iterations', 'seconds', 'spheroradius_px'],
           rows)
