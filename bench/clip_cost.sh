#!/usr/bin/env bash
# What clipping (no sphere protrudes) costs in shape fidelity: for each grain and sphere count, D on an
# independent grid (mss compare: 100 voxels along the shortest edge, offset 0.37 voxel) unbounded
# (--max-protrusion inf), bounded by one voxel (the default), with
# --clip (spheres chosen under the constraint: "refill"), with --clip --no-refill (the unclipped spheres shrunk
# afterwards), the ratio clip/unclipped, and the spheres --clip needs to reach the unclipped D of the
# generation grid (--dice target). CT-voxels: a voxel volume, clipped to the faces of its solid voxels.
# usage: bench/clip_cost.sh [THREADS]   (build first: scripts/setup.sh)
set -euo pipefail
cd "$(dirname "$0")/.."
MSS=./build/mss
THREADS=${1:-2}
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT

printf '%-12s %-9s %4s %9s %9s %9s %9s %7s %12s\n' grain method n D_free D_bound D_clip D_shrunk ratio n_clip_same_D
run() { # input label method n [extra options for every run]
  local in=$1 label=$2 method=$3 n=$4
  shift 4
  local extra=("$@") d=() gen
  for clip in "--max-protrusion inf" "" "--clip" "--clip --no-refill"; do
    # shellcheck disable=SC2086
    $MSS generate "$in" --spheres "$n" --method "$method" --threads "$THREADS" $clip "${extra[@]}" \
      -o "$OUT/s.csv" > "$OUT/run.log"
    [ "$clip" = "--max-protrusion inf" ] && gen=$(awk '/^dice/{print $2}' "$OUT/run.log")
    # a voxel volume is scored on its own voxels (--resolution and --offset apply to meshes)
    d+=("$($MSS compare "$in" "$OUT/s.csv" --resolution 100 --offset 0.37 ${NPY:+--voxel-size 1} |
      awk '/^dice/{print $2}')")
  done
  local same="-"
  if [ "$method" = optimized ]; then # fewest clipped spheres meeting the unclipped D (generation grid)
    $MSS generate "$in" --dice "$gen" --method "$method" --threads "$THREADS" --clip "${extra[@]}" \
      -o "$OUT/s.csv" > "$OUT/run.log"
    same=$(awk '/^spheres/{print $2}' "$OUT/run.log")
  fi
  printf '%-12s %-9s %4s %9.5f %9.5f %9.5f %9.5f %7.2f %12s\n' "$label" "$method" "$n" "${d[0]}" "${d[1]}" \
    "${d[2]}" "${d[3]}" "$(awk -v a="${d[2]}" -v b="${d[0]}" 'BEGIN{print a / b}')" "$same"
}
F=tests/data/human_femur.stl
for n in 10 30 70 100; do run $F femur optimized "$n" --resolution 103; done
for n in 30 70; do run $F femur paper "$n" --resolution 103; done
for g in ellipsoid_2_1_1 cube octahedron torus stanford_bunny_open; do
  for n in 10 40; do run tests/data/$g.stl "$g" optimized "$n" --resolution 103; done
done
for n in 10 30; do NPY=1 run tests/data/grain_voxels_155x157x167.npy CT-voxels optimized "$n" --voxel-size 1; done
echo "D: Dice mismatch (eq. 27) on an independent grid; ratio = D_clip / D_free; n_clip_same_D: spheres that"
echo "--clip needs to reach, on the generation grid, the D that n unbounded spheres reach there."
