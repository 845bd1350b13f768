#!/usr/bin/env bash
# Redraws the README's pictures of the femur with the command line: mss preview (40 spheres against the mesh)
# and mss curve (D and time for 5 to 100 spheres, CLUMP's real outputs as points), and the manual's mss ochart
# (D, cost and O over 4 to 64 spheres and five radius bounds; the cheapest clump with D <= 0.05).
# usage: bash docs/make_pictures.sh   (after bash scripts/setup.sh)
set -euo pipefail
cd "$(dirname "$0")/.."
MSS=./build/mss
FEMUR=tests/data/human_femur.stl
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
# SI units: the mesh is in millimetres (--scale 1e-3); the curve stays in them, as CLUMP's files are
$MSS generate $FEMUR --spheres 40 --resolution 103 --scale 1e-3 -o "$tmp/femur_40.txt" --preview docs/femur40_preview.png
$MSS curve $FEMUR --counts 5:100 -o docs/femur_curve.png \
  --compare tests/data/clump/FA_femur_N70_min.txt tests/data/clump/FM_femur_n70_dmin2_rmin1_rstep0.1_seed5.txt
$MSS ochart $FEMUR --counts 4:64 --dice 0.05 --min-cost --scale 1e-3 -o "$tmp/femur_ochart.png"
cp "$tmp/femur_ochart.png" docs/femur_ochart.png
# the surface of the femur's 70 spheres (mss surface), shaded
$MSS generate $FEMUR --spheres 70 --scale 1e-3 -o "$tmp/femur_70.csv" > /dev/null
$MSS surface "$tmp/femur_70.csv" --tolerance 0.005 -o "$tmp/femur_70_surface.ply" > /dev/null
PYTHONPATH=build/py /usr/bin/python3 docs/draw_surface.py "$tmp/femur_70_surface.ply" docs/femur70_surface.png
