# Scripted comparison with CLUMP: its real outputs for the femur, the ellipsoid and the cube (tests/data/clump:
# CLUMP_Python's Euclidean, Favier and Ferellec-McDowell generators, text and VTK files) next to yade-mss at the
# same sphere counts, all scored on one independent grid, in one table; then the femur's D-vs-n chart with
# CLUMP's points on it (out/compare_clump_femur.png; MSS_OUT sets the folder).
# Run: yade -n -x examples/compare_clump.py    (or /usr/bin/python3 examples/compare_clump.py)
import glob
import os

from yade_mss import compareMany, generate
from yade_mss.pictures import curve

data = os.environ.get('MSS_DATA', os.path.join('tests', 'data'))
grains = {'femur': 'human_femur.stl', 'ellipsoid': 'ellipsoid_2_1_1.stl', 'cube': 'cube.stl'}
names = {'EU': 'CLUMP Euclidean', 'FA': 'CLUMP Favier', 'FM': 'CLUMP Ferellec-McDowell'}

print('%-10s %-26s %4s %8s %9s %9s %9s' % ('grain', 'generator', 'n', 'D', 'protr/L', 'mass', 'inertia'))
lost = []
mine = {}  # (grain, n): our row, generated once
for grain, mesh in grains.items():
    target = os.path.join(data, mesh)
    for path in sorted(glob.glob(os.path.join(data, 'clump', '*_%s_*.txt' % grain))):
        kind = os.path.basename(path)[:2]
        try:
            theirs = compareMany(target, [path])[0]
        except ValueError as e:  # in another frame: CLUMP_Python's Euclidean generator does not shift its
            print('%-10s %-26s refused as written (%s...): registered by the bounding boxes'  # spheres back
                  % (grain, names[kind], str(e)[:40]))
            theirs = compareMany(target, [path], align='bbox')[0]
        n = theirs['spheres']
        if (grain, n) not in mine:
            mine[(grain, n)] = compareMany(target, [generate(target, nSpheres=n, resolution=103)])[0]
        ours = mine[(grain, n)]
        size = max(theirs['grid']['dims']) * theirs['grid']['voxelSize']
        for label, row in ((names[kind], theirs), ('yade-mss', ours)):
            print('%-10s %-26s %4d %8.4f %9.4f %+9.4f %9.4f' % (grain, label, row['spheres'], row['dice'],
                                                                row['protrusion'] / size, row['massError'],
                                                                row['inertiaError']))
        if not ours['dice'] < theirs['dice']:
            lost.append('%s %s' % (grain, names[kind]))
print('D: Dice mismatch (eq. 27), 100 voxels along the shortest edge, offset 0.37 voxel; protr/L: largest '
      'protrusion over the grain\'s size; mass, inertia: the spheres\' union against the grain (relative)')
# the D-vs-n chart of the femur (mss curve), CLUMP's femur outputs as points on it
out = os.environ.get('MSS_OUT', 'out')
os.makedirs(out, exist_ok=True)
chart = os.path.join(out, 'compare_clump_femur.png')
others = sorted(glob.glob(os.path.join(data, 'clump', '*_femur_*.txt')))
others = [f for f in others if not os.path.basename(f).startswith('EU')]  # the EU file is in another frame
rows = curve(os.path.join(data, 'human_femur.stl'), 10, 100, chart,
             points=4 if os.environ.get('MSS_SHORT') == '1' else 10, compare=others)
print('chart        %s (and its .csv): D from %.4f at n %d to %.4f at n %d, CLUMP\'s femur files as points'
      % (chart, rows[0]['D'], rows[0]['n'], rows[-1]['D'], rows[-1]['n']))
if lost:
    raise SystemExit('yade-mss did not beat CLUMP on: ' + ', '.join(lost))
