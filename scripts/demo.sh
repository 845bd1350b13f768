#!/usr/bin/env bash
# Set-up, then the main job on a bundled grain: the human femur (X-ray CT) to a 70-sphere clump.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh main
echo "== yade -n -x examples/quickstart.py: the femur (X-ray CT) to a 70-sphere YADE clump, dropped on a plane"
yade -n -x examples/quickstart.py 2>&1 | grep -v -E "^(Welcome|TCP|XMLRPC|Running script|Using python)"
mkdir -p out
./build/mss generate tests/data/human_femur.stl --spheres 70 --resolution 103 -o out/femur_70.txt > /dev/null
./build/mss generate tests/data/human_femur.stl --spheres 70 --resolution 103 -o out/femur_70.vtk > /dev/null
echo "== also wrote out/femur_70.txt (YADE text clump) and out/femur_70.vtk (ParaView) with the mss command"
