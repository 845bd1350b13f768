#!/usr/bin/python3
"""The manual's figure of a clump pair's stiffness against the sphere count (docs/guide/yade.rst), with YADE's own
contacts and with contactStiffness='grain', from the newest part-1 rows of bench/results/pair_stiffness.csv
(``yade -n -x bench/pair_stiffness.py``, MSS_PARTS=1). Run from the root: /usr/bin/python3
docs/make_pair_figure.py (writes docs/pair_stiffness.png)."""
import csv
import os
import sys

import matplotlib
matplotlib.use('Agg')
import matplotlib.pyplot as plt  # noqa: E402

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..')
COUNTS = (5, 10, 20, 30, 70)


def rows():
    with open(os.path.join(ROOT, 'bench', 'results', 'pair_stiffness.csv')) as f:
        pair = [r for r in csv.DictReader(f) if r['part'] == 'pair']
    if not pair:
        sys.exit('no part-1 rows in bench/results/pair_stiffness.csv: run the bench first')
    newest = max(r['date'] for r in pair)
    return [r for r in pair if r['date'] == newest]


def main(out=os.path.join(ROOT, 'docs', 'pair_stiffness.png')):
    got = rows()
    directions = sorted(set(r['direction'] for r in got), key=lambda d: ('tip', 'side', '45 deg').index(d)
                        if d in ('tip', 'side', '45 deg') else 9)
    fig, axes = plt.subplots(1, len(directions), figsize=(11, 3.6), sharey=True)
    for ax, d in zip(axes, directions):
        for r in got:
            if r['direction'] != d or r['overlap'] not in ('0.005', '0.02'):
                continue
            grain = r['contactStiffness'] == 'grain'
            ax.plot(COUNTS, [float(r['K_n%d' % n]) for n in COUNTS], 'o-' if grain else 's--',
                    color='C0' if grain else 'C3', alpha=1.0 if r['overlap'] == '0.02' else 0.5,
                    label="%s, %.1f %% overlap" % ("'grain'" if grain else "YADE's own", 100 * float(r['overlap'])))
        ref = float(got[0]['reference'])
        ax.axhline(ref, color='k', lw=0.8, ls=':', label='one contact of the grains (E R)')
        ax.set_xscale('log')
        ax.set_yscale('log')
        ax.set_xticks(COUNTS)
        ax.set_xticklabels([str(n) for n in COUNTS])
        ax.set_xlabel('spheres per clump')
        ax.set_title({'tip': 'tip to tip', 'side': 'side to side', '45 deg': 'at 45 degrees'}.get(d, d))
        ax.grid(True, which='both', alpha=0.3)
    axes[0].set_ylabel('pair stiffness F / overlap (N/m)')
    axes[-1].legend(fontsize=7, loc='upper left')
    fig.suptitle('Two clumps of the ellipsoid, fixed, FrictMat young 1e8, linear law (bench/pair_stiffness.py, %s)'
                 % got[0]['date'][:10], fontsize=9)
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    print('wrote', out)


if __name__ == '__main__':
    main()
