#!/usr/bin/env bash
# Set-up, then the main job on a bundled grain: the human femur (X-ray CT) to a 70-sphere clump.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
mkdir -p out
echo "== mss generate tests/data/human_femur.stl --spheres 70 --resolution 103 (the paper's grid)"
./build/mss generate tests/data/human_femur.stl --spheres 70 --resolution 103 -o out/femur_70.txt
./build/mss generate tests/data/human_femur.stl --spheres 70 --resolution 103 -o out/femur_70.vtk > /dev/null
echo "== scored on an independent grid (100 voxels along the shortest edge, offset 0.37 voxel)"
./build/mss compare tests/data/human_femur.stl out/femur_70.txt
echo "== wrote out/femur_70.txt (YADE text clump: ymport.textClumps) and out/femur_70.vtk (ParaView)"
