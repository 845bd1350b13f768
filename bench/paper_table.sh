#!/usr/bin/env bash
# Reproduces the MSS paper's benchmarks (section 4: ellipsoid 10 spheres, femur 70) and more sphere counts.
# Modes: bounded (the default: no sphere more than one voxel beyond the mesh), unbounded (--max-protrusion inf,
# the behaviour before the bound), clip (--clip: none beyond), paper (the published procedure, bounded).
# For each run: n, D on an independent grid (mss compare: 100 voxels along the shortest edge, offset by 0.37
# voxel from the centred placement, so no result is scored on the voxels it was fitted to), D on the generation
# grid, wall time end to end (read STL .. write spheres) and per phase, peak memory per voxel of the grid.
# Times are the fastest of REPEAT runs (default 3). Each run is also a row of bench/results/paper_table.csv.
# usage: [REPEAT=N] bench/paper_table.sh [THREADS]   (build first: scripts/setup.sh)
set -euo pipefail
cd "$(dirname "$0")/.."
MSS=./build/mss
THREADS=${1:-2}
REPEAT=${REPEAT:-3}
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT
source bench/lib.sh
TIME=""
[ -x /usr/bin/time ] && TIME="/usr/bin/time -f %M -o $OUT/mem"

printf '%-10s %-9s %4s %9s %9s %6s %7s %7s %7s %7s %7s %7s %8s\n' grain mode n D_indep D_gen prot total read voxel edt select refine B/voxel
run() { # mesh label mode n [extra generate options]
  local mesh=$1 label=$2 mode=$3 n=$4
  shift 4
  local extra=("$@") method=optimized
  case $mode in
    unbounded) extra+=(--max-protrusion inf) ;;
    clip) extra+=(--clip) ;;
    paper) method=paper ;;
  esac
  # best of REPEAT runs (these machines are noisy); the output is the same every run
  local best=1e9 t
  for _ in $(seq "$REPEAT"); do
    $TIME $MSS generate "$mesh" --spheres "$n" --resolution 103 --method "$method" --threads "$THREADS" \
      "${extra[@]}" -o "$OUT/s.csv" > "$OUT/run.log" 2> /dev/null
    t=$(awk '/^seconds/{print $NF}' "$OUT/run.log")
    if awk -v a="$t" -v b="$best" 'BEGIN{exit !(a < b)}'; then best=$t; cp "$OUT/run.log" "$OUT/gen.log"; fi
  done
  local dgen grid secs dind mem vox bpv h prot
  dgen=$(awk '/^dice/{print $2}' "$OUT/gen.log")
  grid=$(awk '/^grid/{print $2*$4*$6}' "$OUT/gen.log")
  secs=$(awk '/^seconds/{print $3, $5, $7, $9, $11, $13}' "$OUT/gen.log")
  h=$(awk '/^grid/{print $NF}' "$OUT/gen.log")
  $MSS compare "$mesh" "$OUT/s.csv" --resolution 100 --offset 0.37 > "$OUT/cmp.log"
  dind=$(awk '/^dice/{print $2}' "$OUT/cmp.log")
  # largest protrusion beyond the mesh (compare: sampled, exact distances), in voxels of the generation grid
  prot=$(awk -v h="$h" '/^protrusion/{printf "%.2f", $2 / h}' "$OUT/cmp.log")
  bpv="-"
  if [ -n "$TIME" ]; then mem=$(tail -1 "$OUT/mem"); bpv=$(awk -v m="$mem" -v v="$grid" 'BEGIN{printf "%.1f", m*1024/v}'); fi
  read -r tread tvox tedt tsel tref ttot <<<"$secs"
  printf '%-10s %-9s %4s %9.5f %9.5f %6s %7.3f %7.3f %7.3f %7.3f %7.3f %7.3f %8s\n' "$label" "$mode" "$n" "$dind" "$dgen" "$prot" \
    "$ttot" "$tread" "$tvox" "$tedt" "$tsel" "$tref" "$bpv"
  bench_row paper_table.csv grain,mode,n,dice_independent,dice_generation,protrusion_voxels,seconds_total \
    "$label" "$mode" "$n" "$dind" "$dgen" "$prot" "$ttot"
}
for mode in bounded unbounded clip paper; do
  run tests/data/ellipsoid_2_1_1.stl ellipsoid "$mode" 10
  for n in 10 20 30 50 70 100; do run tests/data/human_femur.stl femur "$mode" "$n"; done
done
echo "the other shared grains (bars: cube 30 <= 0.07, octahedron 30 <= 0.06, torus 40 <= 0.02, bounded)"
for mode in bounded unbounded; do
  run tests/data/cube.stl cube "$mode" 30
  run tests/data/octahedron.stl octahedron "$mode" 30
  run tests/data/torus.stl torus "$mode" 40
done
echo "femur 70 clipped without refill (generate freely, shrink afterwards):"
run tests/data/human_femur.stl femur+shrink clip 70 --no-refill
echo "prot: largest protrusion beyond the mesh in voxels of the generation grid (mss compare, sampled exactly)"
echo "grids: ellipsoid 210x107x107, femur 128x107x206 (--resolution 103; paper: 209x107x107, 127x107x205)"
echo "peak memory per voxel is the whole process (mesh, hit lists, all grids) over the generation grid's voxels"
