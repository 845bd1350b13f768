"""Writes the manual's generated pages into a folder: the command-line reference from the option table (the
one the command line, the binding and the docstrings are made from) and the results tables from the rows the
benches wrote under bench/results. Run by scripts/docs.sh; nothing here is typed by hand.

usage: PYTHONPATH=build/py python3 docs/gen_reference.py OUTDIR
       python3 docs/gen_reference.py --readme README.md        (the README's results block, the same way)
       python3 docs/gen_reference.py --check-readme README.md  (fails when it is not the newest rows)"""

import csv
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
RESULTS = os.path.join(HERE, '..', 'bench', 'results')
COMMANDS = (('generate', 'mss generate INPUT -o OUT [options]', 'Spheres for a mesh (.stl .obj .off .ply) or a '
             'voxel volume (.npy). Give at least one termination criterion: ``--spheres``, ``--eta``, ``--dice`` '
             'or ``--rmin`` (paper section 3.5).'),
            ('compare', 'mss compare INPUT SPHERES... [options]', 'Scores sphere files of any generator against the '
             'grain on a grid of its own; several files give one table.'),
            ('info', 'mss info INPUT [options]', 'What was read: mesh closedness and defects, volume; voxel counts.'),
            ('batch', 'mss batch INPUT... -o DIR [options]', 'A labelled CT volume or a folder of grains to a DEM '
             'assembly; every generation option applies to each grain.'),
            ('preview', 'mss preview GRAIN SPHERES -o OUT.png [options]', 'A clump against its grain: three views '
             'and a section.'),
            ('curve', 'mss curve GRAIN --counts A:B -o OUT.png [options]', 'D and the generation time against the '
             'sphere count, as a chart and a CSV.'),
            ('ochart', 'mss ochart GRAIN -o OUT.png [--counts A:B --radii A:B] [--dice X --min-cost]', 'D, the '
             'simulation cost T = n / r_min and O = T x D over sphere counts and radius bounds (the O-chart in '
             '3-D), with the Pareto front; ``--dice X --min-cost`` writes the cheapest clump meeting D <= X.'),
            ('export', 'mss export GRAIN|RESULT.npz --format liggghts|kratos|mercurydpm|pfc|yade -o OUT [options]',
             'A clump as another DEM code\'s template with the grain\'s exact mass, centre and inertia (see '
             ':doc:`/guide/export`).'),
            ('surface', 'mss surface SPHERES -o MESH.stl|.obj|.ply [options]', 'The boundary of the spheres\' '
             'union as a closed, outward triangle mesh, within ``--tolerance`` of the union\'s exact volume (see '
             ':doc:`/guide/surface`).'),
            ('spheropolygon', 'mss spheropolygon IMAGE -o OUT.json [options]', '2-D particle images (.npy, .png) '
             'to spheropolygons (the second paper), with the O-chart.'),
            ('triaxial', 'mss triaxial GRAIN|FOLDER|BATCH_DIR|SPHERES -o DIR --spheres N,N,... [options]', 'A triaxial '
             'test of the grains\' clumps in YADE, the same specimen at each sphere count (see '
             ':doc:`/tutorials/triaxial`); every generation option applies to each grain.'))


def esc(text):
    """reST-safe inline text: backslashes, stars, backquotes and pipes escaped (a table's cells)."""
    for c in '\\*`|_':
        text = text.replace(c, '\\' + c)
    return text


def table(header, rows, widths=None):
    """A reST list-table."""
    out = ['.. list-table::', '   :header-rows: 1']
    if widths:
        out.append('   :widths: ' + ' '.join(str(w) for w in widths))
    out.append('')
    for r in [header] + rows:
        out.append('   * - ' + (r[0] or ' '))
        out += ['     - ' + (c or ' ') for c in r[1:]]
    return '\n'.join(out) + '\n'


def cliReference(table_rows, _options):
    out = ['Command-line reference', '======================', '',
           'Made from the option table (``pkg/mss/generation/option_table.cpp``), as ``mss COMMAND --help`` is: each option has '
           'one name and one meaning in every command that takes it; the Python keyword is the same option in '
           ':func:`yade_mss.generate`, :func:`yade_mss.compareMany` and :func:`yade_mss.batch`.', '']
    for cmd, usage, text in COMMANDS:
        out += ['``mss %s``' % cmd, '-' * (len(cmd) + 8), '', '::', '', '    ' + usage, '', text, '']
        rows = []
        for r in table_rows:
            if cmd not in r['commands'] or not r['flag']:
                continue
            flag = r['flag'].split(',')
            value = '' if r['type'] == 'bool' else ' ' + r['metavar']
            extra = _options.facts(r, withDefault=False)
            rows.append(['``%s``' % (', '.join(flag) + value), '``%s``' % r['name'] if r['python'] else '',
                         esc(r['help']) + (' [%s]' % esc('; '.join(extra)) if extra else ''),
                         esc(r['default'])])
        out.append(table(['option', 'Python', 'meaning', 'default'], rows, (22, 14, 54, 10)))
    return '\n'.join(out)


def readRows(name):
    path = os.path.join(RESULTS, name)
    if not os.path.exists(path):
        return []
    with open(path, newline='') as f:
        return list(csv.DictReader(f))


def latest(rows, key):
    """The newest row for each key (rows are appended in time order)."""
    out = {}
    for r in rows:
        out[key(r)] = r
    return out


def fidelity():
    rows = readRows('paper_table.csv')
    if not rows:
        return 'No rows yet: run ``bash bench/paper_table.sh``.\n'
    last = latest(rows, lambda r: (r['grain'], r['mode'], r['n']))
    grains = [('femur', n) for n in ('10', '20', '30', '50', '70', '100')] + [('ellipsoid', '10')]
    modes = (('bounded', 'default (one voxel)'), ('unbounded', '``--max-protrusion inf``'), ('clip', '``--clip``'),
             ('paper', "the paper's procedure"))
    body = []
    for mode, label in modes:
        cells = [last.get((g, mode, n), {}).get('dice_independent', '') for g, n in grains]
        body.append([label] + [('%.3g' % float(c)) if c else '' for c in cells])
    dates = sorted({r['date'][:10] for r in last.values()})
    commits = sorted({r['commit'] for r in last.values()})
    text = table(['D (eq. 27)'] + ['femur %s' % n for g, n in grains if g == 'femur'] + ['ellipsoid 10'], body)
    return text + '\nRows of %s, commit %s (bench/results/paper_table.csv).\n' % (', '.join(dates), ', '.join(commits))


def speed():
    rows = readRows('speed.csv')
    if not rows:
        return 'No rows yet: run ``bash bench/speed.sh``.\n'
    last = latest(rows, lambda r: r['case'])
    body = [[esc(r['case']), r['median_s'], r['in_process_median_s'], r['target_s'], r['load'], r['commit']]
            for r in last.values()]
    return table(['case', 'end to end, s', 'in process, s', 'target, s', 'load', 'commit'], body)


def yadeClumps():
    rows = readRows('yade_clumps.csv')
    if not rows:
        return 'No rows yet: run ``yade -n -x bench/yade_clumps.py``.\n'
    last = latest(rows, lambda r: r['clumps'])
    body = [[r['clumps'], r['mssClump_ratio'], r['cloud_ratio'], r['restore_us'], r.get('restore_floor_us', ''),
             r['load'], r['commit']] for r in last.values()]
    return table(['clumps', 'mssClump / appendClumped', 'mssClumpCloud / makeClumpCloud', 'restore, us a clump',
                  'YADE API floor, us', 'load', 'commit'], body)


def polish():
    """The joint polish (--polish): D's change per grain and mode (mean over the counts), then over all."""
    rows = readRows('polish.csv')
    if not rows:
        return 'No rows yet: run ``PYTHONPATH=build/py /usr/bin/python3 bench/polish.py``.\n'
    last = latest(rows, lambda r: (r['grain'], r['spheres'], r['mode']))
    modes = ('bounded', 'unbounded', 'clipped')
    grains = list(dict.fromkeys(r['grain'] for r in last.values()))

    def cell(rs):
        if not rs:
            return ''
        change = sum(float(r['change']) for r in rs) / len(rs)
        ratio = sorted(float(r['seconds_polish']) / float(r['seconds']) for r in rs)[len(rs) // 2]
        return '%+.1f%%, %.1fx' % (100 * change, ratio)

    body = [[esc(g)] + [cell([r for r in last.values() if r['grain'] == g and r['mode'] == m]) for m in modes]
            for g in grains]
    body.append(['all'] + [cell([r for r in last.values() if r['mode'] == m]) for m in modes])
    won = []
    for m in modes:
        w = [float(r['change']) for r in last.values() if r['mode'] == m and float(r['change']) < 0]
        worse = sum(float(r['change']) > 0 for r in last.values() if r['mode'] == m)
        won.append('%d won (mean %+.1f%%), %d worse' % (len(w), 100 * sum(w) / max(1, len(w)), worse))
    body.append(['where it changed the set'] + won)
    counts = sorted({int(r['spheres']) for r in last.values()})
    commits = sorted({r['commit'] for r in last.values()})
    return (table(['grain', 'bounded', 'unbounded', 'clipped'], body) +
            '\nEach cell: the mean change of D over %s spheres, then the median time of a polished generation against '
            'a plain one. Rows of commit %s (bench/results/polish.csv).\n' % (' / '.join(map(str, counts)),
                                                                           ', '.join(commits)))


def markdownTable(header, rows):
    return '\n'.join(['| ' + ' | '.join(header) + ' |', '|' + '---|' * len(header)] +
                     ['| ' + ' | '.join(r) + ' |' for r in rows])


def readmeResults():
    """The README's results: the newest bench rows as markdown tables, with the commands that made them."""
    out = []
    rows = readRows('paper_table.csv')
    if rows:
        last = latest(rows, lambda r: (r['grain'], r['mode'], r['n']))
        cols = [('femur', n) for n in ('10', '20', '30', '50', '70', '100')] + [('ellipsoid', '10')]
        body = []
        for mode, label in (('bounded', 'default (bounded by one voxel)'), ('unbounded', '`--max-protrusion inf`'),
                            ('clip', '`--clip`'), ('paper', "the paper's procedure (bounded)")):
            body.append([label] + [('%.3g' % float(last[(g, mode, n)]['dice_independent']))
                                   if (g, mode, n) in last else '' for g, n in cols])
        commits = sorted({last[k]['commit'] for k in last})
        out += ['Shape fidelity: D (Dice mismatch, eq. 27) on an independent grid, femur and ellipsoid 2:1:1 at '
                'resolution 103 (the paper\'s grids); `bash bench/paper_table.sh` (commit %s):' % ', '.join(commits), '',
                markdownTable(['D'] + ['femur %s' % n for g, n in cols if g == 'femur'] + ['ellipsoid 10'], body), '']
    rows = readRows('speed.csv')
    if rows:
        last = latest(rows, lambda r: r['case'])
        keep = [r for r in last.values() if r['target_s'] != '-']
        commits = sorted({r['commit'] for r in keep})
        out += ['Speed, end to end on %s (process start to spheres written, median of 5); `bash bench/speed.sh` '
                '(commit %s; the manual\'s results page gives each row\'s machine load):'
                % (keep[0]['machine'] if keep else 'this machine', ', '.join(commits)), '',
                markdownTable(['case', 'seconds'], [[r['case'], r['median_s']] for r in keep]), '']
    rows = readRows('yade_clumps.csv')
    if rows:
        last = latest(rows, lambda r: r['clumps'])
        out += ['Clumps in YADE, 10 spheres each; `yade -n -x bench/yade_clumps.py` (time against YADE\'s own of the '
                'same spheres; commit %s):' % ', '.join(sorted({r['commit'] for r in last.values()})), '',
                markdownTable(['clumps', '`mssClump` / `appendClumped`', '`mssClumpCloud` / `makeClumpCloud`',
                               '`restoreClumpProperties`, us a clump'],
                              [[r['clumps'], r['mssClump_ratio'] + 'x', r['cloud_ratio'] + 'x', r['restore_us']]
                               for r in last.values()]), '']
    return '\n'.join(out)


BEGIN, END = '<!-- results: made by docs/gen_reference.py from bench/results -->', '<!-- end of results -->'


def readmeBlock(readme):
    """(text before, the block, text after) of the README's results block."""
    with open(readme) as f:
        text = f.read()
    a, b = text.index(BEGIN) + len(BEGIN), text.index(END)
    return text[:a], text[a:b], text[b:]


def write(path, text):
    tmp = path + '.tmp'
    with open(tmp, 'w') as f:
        f.write(text)
    os.replace(tmp, path)


def main(outdir):
    from yade_mss.grains import optionTable as _options
    os.makedirs(outdir, exist_ok=True)
    write(os.path.join(outdir, 'cli_reference.rst'), cliReference(_options.TABLE, _options))
    write(os.path.join(outdir, 'fidelity.rst'), fidelity())
    write(os.path.join(outdir, 'speed.rst'), speed())
    write(os.path.join(outdir, 'yade_clumps.rst'), yadeClumps())
    write(os.path.join(outdir, 'polish.rst'), polish())


if __name__ == '__main__':
    if sys.argv[1] == '--readme':  # rewrite the README's results block from the newest rows
        before, _, after = readmeBlock(sys.argv[2])
        write(sys.argv[2], before + '\n' + readmeResults() + '\n' + after)
    elif sys.argv[1] == '--check-readme':  # whether it shows them
        _, block, _ = readmeBlock(sys.argv[2])
        if block.strip() != readmeResults().strip():
            sys.exit('docs: the README\'s results are not the newest bench rows: run '
                     'python3 docs/gen_reference.py --readme README.md')
    else:
        main(sys.argv[1])
