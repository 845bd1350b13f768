"""The gallery (docs/_gallery, built with the manual by scripts/docs.sh): every example script a page with what it
prints and the pictures it draws, each run here in real YADE (``yade -n -x``, the short runs: MSS_SHORT=1,
MSS_FIGURES for the pictures), and the report of ``mss batch --segment`` on a synthetic porous sand scan, seen
in headless Chromium. Nothing stored: the pages show what this build's code does. sphinx-gallery runs its
examples in the Python that builds the manual; these are YADE scripts, so they are run here, in YADE, and their
pages written as sphinx-gallery lays them out (code, output, pictures, a thumbnail each on the index).
Run: PYTHONPATH=build/py MSS_BINARY=build/mss /usr/bin/python3 docs/make_gallery.py docs/_gallery
"""
import concurrent.futures
import glob
import os
import re
import shutil
import subprocess
import sys
import tempfile

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), '..'))
EXAMPLES = {  # each example and its page's title
    'quickstart': 'A CT-scanned femur to one clump, dropped on a plane',
    'ct_specimen': 'A labelled CT volume to a DEM assembly, then compressed',
    'triaxial': 'Triaxial compression of CT-scanned sand grains',
    'compare_clump': 'Scripted comparison with CLUMP',
    'crush_grain': 'One grain crushed between two platens',
    'oedometer_crushing': 'An oedometer of crushable grains',
}
BANNER = re.compile(r'^(Welcome to Yade|Using python version|TCP python prompt|XMLRPC info provider|Running script)')


def header(path):
    """The example's leading comment: (its text as a paragraph, its Run: line)."""
    lines = []
    with open(path) as f:
        for line in f:
            if not line.startswith('#'):
                break
            lines.append(line[1:].strip())
    run = next((l for l in lines if l.startswith('Run:')), '')
    text = ' '.join(l for l in lines if not l.startswith(('Run:', 'Environment:')) and not l.startswith('  '))
    return text.strip(), run[4:].strip()


def runExample(name, work):
    """Runs examples/NAME.py in YADE from the root, its pictures to WORK/NAME: (printed lines, pictures)."""
    figures = os.path.join(work, name)
    os.makedirs(figures)
    env = dict(os.environ, MSS_SHORT='1', MSS_FIGURES=figures, MSS_OUT=figures, MPLBACKEND='Agg')
    p = subprocess.run(['yade', '-n', '-x', os.path.join(ROOT, 'examples', name + '.py')], cwd=ROOT, env=env,
                       capture_output=True, text=True, timeout=1200)
    if p.returncode != 0:
        raise SystemExit('gallery: examples/%s.py failed (exit %d):\n%s%s' % (name, p.returncode, p.stdout[-2000:],
                                                                           p.stderr[-3000:]))
    lines = [l.rstrip() for l in p.stdout.split('\n') if l.strip() and not BANNER.match(l)]
    return lines, sorted(glob.glob(os.path.join(figures, '*.png')))


def batchReport(work):
    """mss batch --segment on a synthetic porous sand scan (yade_mss.porousScan): its console lines and the
    report as Chromium shows it (a screenshot), with the segmentation's picture."""
    import numpy as np
    from yade_mss import porousScan
    d = os.path.join(work, 'batch_report')
    os.makedirs(d)
    scan, _ = porousScan((120, 120, 120), grains=40, size=(12, 20), seed=1)
    np.save(os.path.join(d, 'porous_sand.npy'), scan)
    mss = os.environ.get('MSS_BINARY', os.path.join(ROOT, 'build', 'mss'))
    cmd = ['mss', 'batch', 'porous_sand.npy', '--segment', '--min-voxels', '100', '--spheres', '10',
           '--voxel-size', '1e-5', '--density', '2650', '-o', 'out']
    p = subprocess.run([mss] + cmd[1:], cwd=d, capture_output=True, text=True, timeout=1200)
    if p.returncode != 0:
        raise SystemExit('gallery: mss batch failed:\n' + p.stderr[-3000:])
    profile = tempfile.mkdtemp()
    shot = os.path.join(d, 'report.png')
    subprocess.run(['chromium', '--headless', '--no-sandbox', '--disable-gpu', '--no-first-run',
                    '--user-data-dir=' + profile, '--hide-scrollbars', '--window-size=1300,1700',
                    '--screenshot=' + shot, 'file://' + os.path.join(d, 'out', 'report.html')],
                   capture_output=True, timeout=120)
    shutil.rmtree(profile, ignore_errors=True)
    if not os.path.exists(shot):
        raise SystemExit('gallery: Chromium drew no screenshot of the batch report')
    lines = [l for l in (p.stdout + p.stderr).split('\n') if l.strip() and '\r' not in l and '%|' not in l]
    return ' '.join(cmd), lines, [shot, os.path.join(d, 'out', 'report_segmentation.png')]


def page(out, name, title, text, command, lines, pictures, source=None):
    """Writes OUT/NAME.rst and copies its pictures beside it; returns its thumbnail (the first picture) or None."""
    shown = []
    for k, src in enumerate(pictures):
        dst = '%s_%d.png' % (name, k + 1)
        shutil.copy(src, os.path.join(out, dst))
        shown.append(dst)
    rst = ['.. _gallery_%s:' % name, '', title, '=' * len(title), '', text, '', '.. code-block:: none', '',
           '   ' + command, '']
    if shown:
        for dst in shown:
            rst += ['.. image:: %s' % dst, '   :width: 100%', '']
    rst += ['What it printed (the short run, ``MSS_SHORT=1``):' if source else 'What it printed:', '',
            '.. code-block:: none', ''] + ['   ' + l for l in lines] + ['']
    if source:
        rst += ['The script:', '', '.. literalinclude:: ../../examples/%s.py' % source, '   :language: python', '']
    with open(os.path.join(out, name + '.rst'), 'w') as f:
        f.write('\n'.join(rst))
    return shown[0] if shown else None


def main(out):
    if os.path.exists(out):
        shutil.rmtree(out)
    os.makedirs(out)
    work = tempfile.mkdtemp(prefix='mss_gallery_')
    try:
        with concurrent.futures.ThreadPoolExecutor(max_workers=2) as pool:  # each example a YADE process
            runs = dict(zip(EXAMPLES, pool.map(lambda n: runExample(n, work), EXAMPLES)))
            report = batchReport(work)
        entries = []
        for name in EXAMPLES:
            title = EXAMPLES[name]
            text, run = header(os.path.join(ROOT, 'examples', name + '.py'))
            lines, pictures = runs[name]
            thumb = page(out, name, title, text, run or 'yade -n -x examples/%s.py' % name, lines, pictures, name)
            entries.append((name, title, thumb))
        command, lines, pictures = report
        title = 'The report of a batch: a binary scan of porous sand, segmented'
        text = ('``mss batch --segment`` on a synthetic thresholded micro-CT of 40 touching porous grains (intra-grain '
                'pores, specks, grey-level noise: ``yade_mss.porousScan``): the scan cut into grains, each grain '
                'to a clump, the assembly, and ``report.html``, here as Chromium shows it, with the segmentation\'s '
                'section and the grains\' sizes.')
        entries.append(('batch_report', title, page(out, 'batch_report', title, text, command, lines, pictures)))
    finally:
        shutil.rmtree(work, ignore_errors=True)
    index = ['Gallery', '=======', '',
             'Every example script of ``examples/``, run in YADE when the manual is built (the short runs), with what '
             'it prints and the pictures it draws; and the report of a batch. Nothing here is stored: the pages are '
             'made by ``docs/make_gallery.py`` from this build.', '']
    for name, title, thumb in entries:
        index += ['.. rubric:: :ref:`%s <gallery_%s>`' % (title.replace('`', ''), name), '']
        if thumb:
            index += ['.. image:: %s' % thumb, '   :width: 420px', '   :target: %s.html' % name, '']
    index += ['.. toctree::', '   :hidden:', ''] + ['   %s' % n for n, _, _ in entries] + ['']
    with open(os.path.join(out, 'index.rst'), 'w') as f:
        f.write('\n'.join(index))
    print('gallery: %d pages in %s' % (len(entries), out))


if __name__ == '__main__':
    main(sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, 'docs', '_gallery'))
