#!/usr/bin/env bash
# The manual's figures of what the sphere count does to a triaxial test (docs/tutorials/triaxial.rst): the
# bundled CT grain (2 mm) at 5, 10, 20 and 40 spheres, the same specimen of 80 grains, dense, 100 kPa, drained
# to 10 % axial strain. About 25 minutes on a 2-core machine (the counts two at a time). Run from the root.
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-build/triaxial_study}
mss triaxial tests/data/grain_voxels_155x157x167.npy --voxel-size 1.25e-5 -o "$out" --spheres 5,10,20,40 \
  --grains 80 --strain 0.1 --confining 1e5 --state dense --seed 1 --workers 2
cp "$out/sphere_count.png" docs/triaxial_counts.png
cp "$out/curves.png" docs/triaxial_curves.png
cp "$out/summary.csv" docs/triaxial_study.csv
