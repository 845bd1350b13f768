"""Segmentation of binary scans of porous grains (mss batch --segment): synthetic thresholded scans with the truth
known (yade_mss.specimens.porousScan: touching ellipsoids, intra-grain pores some open to the surface, specks in
the void, grey-level noise thresholded), each cut by the default pipeline (yade_mss.grains.segmentScan) and, for
the record, by the fixed-height pipeline the batch used before (the raw scan's distance transform, h-maxima at
h = 1 voxel, a marker watershed, every other piece a grain). Figures: segments against true grains, the median
best-overlap Jaccard index, the share of grains above 0.8, seconds. Prints a line a case and appends a row a
case and way to bench/results/segmentation.csv.
Run: PYTHONPATH=build/py /usr/bin/python3 bench/segmentation.py"""
import os
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from batch_scale import appendRows  # noqa: E402

import numpy as np  # noqa: E402

from yade_mss.grains import segmentScan  # noqa: E402
from yade_mss.specimens import bestOverlap, porousScan  # noqa: E402

CASES = [  # (name, porousScan's keywords)
    ('12-20 vox, 10 % pores', dict(shape=(120, 120, 120), grains=40, size=(12, 20), porosity=0.1, seed=1)),
    ('12-20 vox, 10 % pores', dict(shape=(120, 120, 120), grains=40, size=(12, 20), porosity=0.1, seed=2)),
    ('12-20 vox, 10 % pores', dict(shape=(120, 120, 120), grains=40, size=(12, 20), porosity=0.1, seed=3)),
    ('14-26 vox, 10 % pores', dict(shape=(160, 160, 160), grains=40, size=(14, 26), porosity=0.1, seed=4)),
    ('16-28 vox, 15 % pores', dict(shape=(140, 140, 140), grains=30, size=(16, 28), porosity=0.15, seed=1)),
    ('12-20 vox, 20 % pores', dict(shape=(120, 120, 120), grains=40, size=(12, 20), porosity=0.2, seed=1)),
    ('12-20 vox, noise 0.45', dict(shape=(120, 120, 120), grains=40, size=(12, 20), noise=0.45, seed=2)),
    ('7-12 vox, 10 % pores', dict(shape=(80, 80, 80), grains=80, size=(7, 12), porosity=0.1, seed=2)),
]


def fixedHeight(scan, h=1.0):
    """The pipeline before: the raw scan's transform, h-maxima, watershed, the rest a grain each."""
    from scipy import ndimage
    from skimage.morphology import h_maxima
    from skimage.segmentation import watershed
    solid = scan != 0
    dist = ndimage.distance_transform_edt(solid)
    markers, n = ndimage.label(h_maxima(dist, h))
    labels = watershed(-dist, markers, mask=solid).astype(np.int32)
    rest, _ = ndimage.label(solid & (labels == 0))
    labels[rest != 0] = rest[rest != 0] + n
    return labels


def main():
    rows = []
    for name, kw in CASES:
        scan, truth = porousScan(**kw)
        for way, cut in (('default', lambda s: segmentScan(s, minVoxels=100)[0]), ('h=1 before', fixedHeight)):
            t0 = time.perf_counter()
            labels = cut(scan)
            seconds = time.perf_counter() - t0
            j = np.array(bestOverlap(labels, truth))
            row = [name, kw['seed'], way, int(truth.max()), int(np.unique(labels[labels != 0]).size),
                   float(np.median(j)), float(np.mean(j > 0.8)), seconds]
            rows.append(row)
            print('%-22s seed %d  %-10s  %3d grains  %5d segments  median J %.3f  %3.0f %% above 0.8  %.1f s'
                  % (name, kw['seed'], way, row[3], row[4], row[5], 100 * row[6], seconds), flush=True)
    print('rows appended to', appendRows('segmentation.csv', ['case', 'seed', 'way', 'grains', 'segments',
                                                             'median_jaccard', 'share_above_0.8', 'seconds'], rows))


if __name__ == '__main__':
    main()
