"""A triaxial study's pictures (the curves; each result and the cost against the sphere count) and its report
page (matplotlib's Agg backend: no display needed)."""

import html
import math
import os

from ..base import atomicWrite
from ._analysis import QUASI_STATIC_I, QUASI_STATIC_UNBALANCED

# The quantities drawn against the sphere count: column, label, factor to the unit shown
RESULTS = (('phi_peak_deg', 'peak friction angle (deg)', 1.0), ('phi_cs_deg', 'critical-state friction angle (deg)', 1.0),
           ('psi_max_deg', 'largest dilatancy angle (deg)', 1.0), ('E50_Pa', 'E50 (MPa)', 1e-6),
           ('e0', 'void ratio at the start of shearing', 1.0))


def _pyplot():
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    return plt


def _save(fig, path):
    def write(tmp):
        fig.savefig(tmp, dpi=110, format='png')
    atomicWrite(path, write, 'triaxial')


def drawCurves(path, records, title):
    """q/p and the volumetric strain against the axial strain, a line a sphere count."""
    plt = _pyplot()
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.2))
    for n in sorted(set(r['n'] for r in records)):
        rs = [r for r in records if r['n'] == n]
        a = [100 * r['axial_strain'] for r in rs]
        ax[0].plot(a, [r['q_over_p'] for r in rs], label='n = %d' % n)
        ax[1].plot(a, [100 * r['volumetric_strain'] for r in rs], label='n = %d' % n)
    ax[0].set_ylabel('q / p')
    ax[1].set_ylabel('volumetric strain (%, compaction positive)')
    for a in ax:
        a.set_xlabel('axial strain (%)')
        a.grid(alpha=0.3)
        a.legend(fontsize=8)
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    _save(fig, path)
    plt.close(fig)


def _countAxis(ax, n):
    """The sphere counts on a log axis, each labelled plainly."""
    from matplotlib.ticker import NullFormatter, NullLocator
    ax.set_xscale('log')
    ax.xaxis.set_minor_locator(NullLocator())
    ax.xaxis.set_minor_formatter(NullFormatter())
    ax.set_xticks(n)
    ax.set_xticklabels([str(x) for x in n])
    ax.set_xlabel('spheres a grain, n')


def drawCounts(path, rows, title):
    """Each result against the sphere count (its change from the largest count's in the legend), and the cost."""
    plt = _pyplot()
    rows = sorted(rows, key=lambda r: r['n'])
    n = [r['n'] for r in rows]
    fig, axes = plt.subplots(2, 3, figsize=(12, 6.5))
    for ax, (key, label, f) in zip(axes.ravel(), RESULTS):
        y = [f * r[key] for r in rows]
        ax.plot(n, y, 'o-')
        if key == 'e0':
            ax.plot(n, [r['e0_union'] for r in rows], 's--', label='on the clumps\' own volumes')
            ax.plot([], [], 'o-', color='C0', label='on the grains\' exact volumes')
            ax.legend(fontsize=7)
        last = y[-1]
        for x, v in zip(n, y):
            if last and math.isfinite(v):  # a void ratio near 0 has no meaningful relative change
                text = ('%+.3f' % (v - last)) if key == 'e0' else ('%+.1f%%' % (100 * (v - last) / abs(last)))
                ax.annotate(text, (x, v), textcoords='offset points', xytext=(3, 4), fontsize=7)
        _countAxis(ax, n)
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
    ax = axes.ravel()[-1]
    ax.plot(n, [r['wall_s'] for r in rows], 'o-', label='wall time (s)')
    ax.plot(n, [r['steps'] / 1e3 for r in rows], 's--', label='steps (thousands)')
    _countAxis(ax, n)
    ax.set_ylim(bottom=0)
    ax.set_ylabel('cost')
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3)
    fig.suptitle(title + '\n(labels: the change from the largest n, relative; for the void ratio, the difference)', fontsize=10)
    fig.tight_layout()
    _save(fig, path)
    plt.close(fig)


def needed(rows, key='phi_peak_deg', within=1.0):
    """The smallest count whose result, and that of every larger count, lies within *within* of the largest
    count's; None when only the largest does (the sweep does not show convergence)."""
    rows = sorted(rows, key=lambda r: r['n'])
    if len(rows) < 2:
        return None
    ref = rows[-1][key]
    best = None
    for r in reversed(rows[:-1]):
        if abs(r[key] - ref) <= within:
            best = r
        else:
            break
    return best


def verdict(rows):
    """The report's sentence on how many spheres the grain needs for its peak angle within 1 degree."""
    rows = sorted(rows, key=lambda r: r['n'])
    if len(rows) < 2:
        return 'One sphere count was tested: run two or more (--spheres 5,10,20,40) to see what the count does.'
    top = rows[-1]
    b = needed(rows)
    if b is None:
        return ('The peak friction angle has not settled within 1 degree over n = %s: at n = %d it is %.1f deg, '
                'at n = %d %.1f deg. Try larger counts.' % (', '.join(str(r['n']) for r in rows), rows[-2]['n'],
                                                            rows[-2]['phi_peak_deg'], top['n'], top['phi_peak_deg']))
    return ('This grain needs n = %d spheres for its peak friction angle within 1 degree of n = %d\'s (%.1f against '
            '%.1f deg), at %.2g of its cost in wall time (%.3g s against %.3g s) and %.2g of its steps.'
            % (b['n'], top['n'], b['phi_peak_deg'], top['phi_peak_deg'], b['wall_s'] / top['wall_s'], b['wall_s'],
               top['wall_s'], b['steps'] / top['steps']))


def _warnings(rows):
    out = []
    for r in rows:
        if not r['quasi_static']:
            out.append('n = %d was not quasi-static: largest inertial number %.2g (bound %g), median unbalanced force '
                       '%.2g (bound %g): lower the inertial number' % (r['n'], r['I_max'], QUASI_STATIC_I,
                                                                       r['unbalanced_median'], QUASI_STATIC_UNBALANCED))
        if not r['peak_reached']:
            out.append('n = %d: q/p was still rising at the end (largest at axial strain %.3g of %.3g): the peak angle '
                       'is a lower bound; shear further (--strain)' % (r['n'], r['strain_at_peak'], r['strain_end']))
        if not r['critical_state']:
            out.append('n = %d: no critical state at the end (d eps_v / d eps_a = %.2f over the last fifth, not '
                       'about 0): phi_cs is the angle there, not the critical-state one; shear further'
                       % (r['n'], r['dvol_rate_end']))
        ratio = (1 + r['e0']) / (1 + r['e0_union'])  # the clumps' volume over the grains'
        if abs(1 - ratio) > 0.05:
            out.append('n = %d: the void ratio on the clumps\' own volumes (%.3f) differs from that on the grains\' '
                       'exact volumes (%.3f): the clumps hold %.0f%% of their grains\' volume, so they pack into '
                       'each other\'s true shape' % (r['n'], r['e0_union'], r['e0'], 100 * ratio))
    return out


def writeReport(outdir, rows, records, failed, unfinished):
    """The pictures and OUT/report.html."""
    title = 'triaxial test, %s' % os.path.basename(os.path.abspath(outdir))
    if records:
        drawCurves(os.path.join(outdir, 'curves.png'), records, title + ': q/p and volumetric strain')
    if len(rows) >= 2:
        drawCounts(os.path.join(outdir, 'sphere_count.png'), rows, title + ': each result against the sphere count')
    e = html.escape
    head = ('n', 'phi_peak_deg', 'phi_cs_deg', 'psi_max_deg', 'E50_Pa', 'e0', 'e0_union', 'I_max', 'quasi_static',
            'steps', 'wall_s')
    table = '<tr>%s</tr>' % ''.join('<th>%s</th>' % e(h) for h in head)
    for r in sorted(rows, key=lambda r: r['n']):
        table += '<tr>%s</tr>' % ''.join('<td>%s</td>' % e('%.4g' % r[h] if isinstance(r[h], float) else str(r[h]))
                                         for h in head)
    notes = ''.join('<li>%s</li>' % e(w) for w in _warnings(rows))
    notes += ''.join('<li>n = %d failed: %s</li>' % (n, e(str(why))) for n, why in sorted(failed.items()))
    notes += ''.join('<li>n = %d did not finish (stopped): run the same command again to resume it</li>' % n
                     for n in unfinished)
    pics = ''.join('<p><img src="%s" alt="%s" style="max-width:100%%"></p>' % (e(p), e(p))
                   for p in ('curves.png', 'sphere_count.png') if os.path.exists(os.path.join(outdir, p)))
    page = ('<!DOCTYPE html><html><head><meta charset="utf-8"><title>%s</title><style>body{font-family:sans-serif;'
            'max-width:1100px;margin:auto}table{border-collapse:collapse}td,th{border:1px solid #bbb;padding:3px 6px;'
            'text-align:right}</style></head><body><h1>%s</h1><p>%s</p><table>%s</table><ul>%s</ul>%s<p>Records: '
            'triaxial.csv; a row a count: summary.csv, summary.json. Compression positive; p and q in Pa; the void '
            'ratio on the grains\' exact volumes and on the clumps\' own (union) volumes.</p></body></html>'
            % (e(title), e(title), e(verdict(rows)) if rows else 'No count finished.', table, notes, pics))

    def write(tmp):
        with open(tmp, 'w') as f:
            f.write(page)
    atomicWrite(os.path.join(outdir, 'report.html'), write, 'triaxial')
