"""``mss spheropolygon``: 2-D particle images to spheropolygons (:func:`yade_mss.spheropolygon`)."""

import argparse
import json
import os
import sys

import numpy as np

from ..base import atomicWrite
from ..grains import optionTable
from ..spheropolygons import ochart, previewSpheropolygon, readImage, spheropolygon


def main(argv=None):
    p = argparse.ArgumentParser(prog='mss spheropolygon', allow_abbrev=False,
                                description='2-D particle images to spheropolygons '
                                '(Dobrohotoff et al. 2012)')
    p.add_argument('image', help='.npy (non-zero: particle; labels: one spheropolygon each) or .png (dark: particle)')
    optionTable.addArguments(p, 'spheropolygon')
    a = p.parse_args(argv)
    try:
        v = optionTable.parsed('spheropolygon', a)
        opt = {r['name']: v.get(r['name'], optionTable.default(r['name'], 'spheropolygon'))
               for r in optionTable.rows('spheropolygon')}
        img = readImage(a.image, opt['threshold'])
        origin = tuple(opt['origin'])
        labels = [None] if img.dtype == bool or len(np.unique(img[img != 0])) <= 1 else \
            [int(l) for l in np.unique(img[img != 0])]
        out = {}
        for l in labels:
            r = spheropolygon(img, opt['vertices'], opt['radius'], opt['pixelSize'], origin, label=l,
                              init=opt['init'], vertexRadii=opt['vertexRadii'], minRadius=opt['minRadius'],
                              regionVertices=opt['regionVertices'], regionTurning=opt['regionTurning'],
                              maxWork=opt['maxWork'])
            keep = ('spheroradius', 'vertices', 'radii', 'errorPixels', 'error', 'iterations', 'roundness', 'area',
                    'perimeter', 'init', 'regions', 'regionsFilled', 'regionsMissed')
            out['particle' if l is None else str(l)] = {k: r[k] for k in keep if k in r}
            print('%-10s N %d  r %s  error %.2f%% (%d pixels)  roundness %.3f  %d iterations%s'
                  % ('particle' if l is None else 'label %d' % l, opt['vertices'],
                     '%.4g' % r['spheroradius'] if 'radii' not in r else
                     '%.4g to %.4g' % (min(r['radii']), max(r['radii'])), 100 * r['error'],
                     r['errorPixels'], r['roundness'], r['iterations'],
                     '  regions %d (%d filled, %d without a vertex)' % (r['regions'], r['regionsFilled'],
                                                                      r['regionsMissed'])
                     if 'regions' in r else ''))
            if opt['preview']:
                base, ext = os.path.splitext(opt['preview'])
                previewSpheropolygon(img != 0 if l is None else img == l, r, opt['preview'] if l is None else
                                     '%s_%d%s' % (base, l, ext), opt['pixelSize'], origin)
        result = out['particle'] if labels == [None] else out

        def dump(tmp):
            with open(tmp, 'w') as f:
                json.dump(result, f, indent=1)
        atomicWrite(opt['output'], dump, 'spheropolygon')
        if opt['ochart']:
            rows = ochart(img, opt['ochart'], pixelSize=opt['pixelSize'], origin=origin,
                          label=None if labels == [None] else labels[0])
            print('ochart     %d (N, r) pairs: %s' % (len(rows), os.path.join(opt['ochart'], 'ochart.csv')))
    except (ValueError, RuntimeError, OSError) as e:
        print('mss spheropolygon: error: %s' % e, file=sys.stderr)
        return 1
    return 0
