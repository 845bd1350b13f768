"""Draws docs/architecture.png: the layers of yade-mss, C++ and Python in one picture, each importing or
including only what is below it. The Python layers are the ones scripts/check_imports.py checks.
usage: /usr/bin/python3 docs/draw_architecture.py docs/architecture.png
"""
import sys

import matplotlib

matplotlib.use('Agg')
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.patches import FancyBboxPatch  # noqa: E402

CPP, BIND, PY, TOP = '#dbe8f6', '#f6e7c8', '#dcefdc', '#eeeeee'

# (x, y, width, height, title, what it holds, colour): x and y in a 16 x 10 grid, bottom up
BOXES = [
    (0.2, 0.3, 7.4, 1.0, 'pkg/mss/platform/', 'threads, cores, memory, the work limit', CPP),
    (0.2, 1.6, 7.4, 1.3, 'pkg/mss/core/', 'grids, meshes, distance transform (eq. 8), maxima (eq. 11-24),\n'
     'mass properties, union volume and surface', CPP),
    (0.2, 3.2, 3.6, 1.3, 'pkg/mss/io/', 'one file a format;\nformats.cpp: their table', CPP),
    (4.0, 3.2, 3.6, 1.3, 'pkg/mss/spheropolygon/', '2-D: the fit\n(second paper)', CPP),
    (0.2, 4.8, 7.4, 1.3, 'pkg/mss/generation/', 'the pipeline, the option table, scoring (eq. 7, 27),\n'
     'comparing, estimates; engine/: one concept a file', CPP),
    (0.2, 6.4, 7.4, 0.9, 'pkg/mss/*.hpp  (pkg/mss.hpp lists them)', 'the public C++ API: what other DEM codes link',
     CPP),
    (0.2, 7.6, 3.6, 1.1, 'app/  (mss)', 'the command line; hands batch,\npreview, ... to python3 -m yade_mss', TOP),
    (4.0, 7.6, 3.6, 1.1, 'py/_mss.cpp', 'the binding, yade_mss._mss: converts\ntypes; every Python layer '
     'reaches\nthe core through it', BIND),
    (8.4, 0.3, 7.4, 1.0, 'yade_mss.base', 'argument checks, keywords, files written whole, work limit', PY),
    (8.4, 1.6, 7.4, 1.3, 'yade_mss.grains', 'sources and volume readers, the option table, generate,\n'
     'score, results, scan contacts  (numpy only: no YADE, no matplotlib)', PY),
    (8.4, 3.2, 2.35, 1.3, 'exports', 'a registry,\none module\na format', PY),
    (10.9, 3.2, 2.35, 1.3, 'pictures', 'preview,\ncurve, ochart', PY),
    (13.4, 3.2, 2.4, 1.3, 'spheropolygons', '2-D images,\nthe O-chart', PY),
    (8.4, 4.8, 7.4, 1.25, 'yade_mss.yade', 'clumps, records, restore, clump files, templates and clouds,\n'
     'breakage: the only layer that imports YADE', PY),
    (8.4, 6.12, 7.4, 0.7, 'yade_mss.specimens', 'batch (local, Dask), report, assembly, synthetic specimens', PY),
    (8.4, 6.88, 7.4, 0.68, 'yade_mss.studies', 'the triaxial test in YADE, the sphere-count study, its report', PY),
    (8.4, 7.6, 3.6, 1.1, 'yade_mss.cli', 'every command\'s parser', PY),
    (12.2, 7.6, 3.6, 1.1, 'yade_mss  (__init__)', 'the user\'s names:\nmssClump, generate, batch, ...', TOP),
]


def main(path):
    fig, ax = plt.subplots(figsize=(13, 8.2), dpi=100)
    ax.set_xlim(0, 16)
    ax.set_ylim(-0.6, 9.6)
    ax.axis('off')
    for x, y, w, h, title, what, colour in BOXES:
        ax.add_patch(FancyBboxPatch((x, y), w, h, boxstyle='round,pad=0.02,rounding_size=0.12', fc=colour,
                                    ec='#555555', lw=1.0))
        ax.text(x + 0.12, y + h - 0.12, title, ha='left', va='top', fontsize=10.5, weight='bold', family='monospace')
        ax.text(x + 0.12, y + h - 0.48, what, ha='left', va='top', fontsize=8.8)
    ax.annotate('', xy=(8.35, 8.15), xytext=(3.85, 8.75),
                arrowprops=dict(arrowstyle='->', color='#777777', lw=1.2, connectionstyle='arc3,rad=-0.12'))
    ax.text(5.6, 9.05, 'python3 -m yade_mss COMMAND', fontsize=8.5, color='#555555', ha='center')
    ax.text(3.9, -0.35, 'C++ (namespace mss): the standard library, Eigen, CGAL', ha='center', fontsize=10,
            style='italic')
    ax.text(12.1, -0.35, 'Python (yade_mss): a sub-package a layer', ha='center', fontsize=10, style='italic')
    ax.set_title('yade-mss in layers: each box uses only the boxes below it (and, in Python, base under all)',
                 fontsize=12)
    fig.tight_layout()
    fig.savefig(path)


if __name__ == '__main__':
    main(sys.argv[1] if len(sys.argv) > 1 else 'docs/architecture.png')
