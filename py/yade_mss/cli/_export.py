"""``mss export``: a clump as another DEM code's template (:func:`yade_mss.exports.exportTemplate`)."""

import argparse
import os
import sys

from .. import _mss
from ..base import refuseOverInputs
from ..exports import checkedOptions, exportTemplate
from ..grains import MssResult, generateWith, optionTable

SPHERE_EXT = tuple(f['extension'] for f in _mss.fileFormats() if f['kind'] == 'spheres')  # the format table's


def _result(source, gen):
    """The result to export: a saved result (.npz) as it is, or a grain generated with *gen*."""
    if isinstance(source, str) and os.path.splitext(source)[1].lower() == '.npz':
        if gen:
            raise ValueError('export: %s is a saved result; generation options (%s) apply to a grain'
                             % (source, ', '.join(sorted(gen))))
        return MssResult.load(source)
    ext = os.path.splitext(source)[1].lower() if isinstance(source, str) else ''
    if ext in SPHERE_EXT:
        raise ValueError('export: %s is a sphere file without its grain: export the grain (mesh or volume) or its '
                         'saved result (.npz), so that the mass properties are the grain\'s' % source)
    return generateWith(source, gen)


def main(argv=None):
    p = argparse.ArgumentParser(prog='mss export', allow_abbrev=False,
                                description='a clump as another DEM code\'s template, with the '
                                'grain\'s exact mass properties (yade-mss)')
    p.add_argument('input', help='a grain (mesh or voxel volume; generated with the options given) or a saved '
                   'result (.npz)')
    optionTable.addArguments(p, 'export')
    a = p.parse_args(argv)
    try:
        v = optionTable.parsed('export', a)
        refuseOverInputs('export', [('-o', v.get('output'))], [a.input])
        own = ('output', 'format', 'density', 'frame', 'templateType', 'atomType')
        gen = {k: x for k, x in v.items() if k not in own}
        r = _result(a.input, gen)
        o = checkedOptions({k: v.get(k) for k in own if k != 'output'})
        exportTemplate(r, v['output'], **o)
    except (ValueError, RuntimeError, OSError) as e:
        print('mss export: error: %s' % e, file=sys.stderr)
        return 1
    m = r.targetMass
    print('wrote       %s  (%s template of %d spheres; mass %.6g = density %g x the grain\'s volume %.6g)'
          % (v['output'], o['format'], len(r), o['density'] * m.volume, o['density'], m.volume))
    return 0
