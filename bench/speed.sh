#!/usr/bin/env bash
# Every speed figure of issue 12 in one run: end-to-end times (STL read to spheres written, as mss reports
# them; median of 5 after an untimed run, 2 threads) against the issue's targets, generation under load
# (bench/load.sh), and how cost grows with grid size and sphere count (bench/cost_growth.py). The machine's
# load is printed first.
# usage: bash bench/speed.sh   (after bash scripts/setup.sh)
set -euo pipefail
cd "$(dirname "$0")/.."
MSS=./build/mss
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT
echo "load: $(cat /proc/loadavg)"
median() { # label target args...: median of 5 end-to-end times, after one untimed run
  local label=$1 target=$2
  shift 2
  local ts=()
  # the first run after an idle spell was 20-30% slower on this VM (femur 70: 0.157-0.163 s, then
  # 0.122-0.135 s): its cores wake slowly; the untimed run also reads the mesh into the page cache
  $MSS generate "$@" --threads 2 -o "$OUT/s.csv" > /dev/null
  for _ in 1 2 3 4 5; do
    $MSS generate "$@" --threads 2 -o "$OUT/s.csv" > "$OUT/run.log"
    ts+=("$(awk '/^seconds/{print $NF}' "$OUT/run.log")")
  done
  printf '%-34s median %6.3f s   target %5s s   (runs: %s)\n' "$label" \
    "$(printf '%s\n' "${ts[@]}" | sort -g | sed -n 3p)" "$target" "${ts[*]}"
}
D=tests/data
median "femur 70, resolution 103" 0.12 $D/human_femur.stl --spheres 70 --resolution 103
median "ellipsoid 10, resolution 103" 0.08 $D/ellipsoid_2_1_1.stl --spheres 10 --resolution 103
median "femur 70, resolution 205" 0.7 $D/human_femur.stl --spheres 70 --resolution 205
median "femur 70 --clip" 0.25 $D/human_femur.stl --spheres 70 --resolution 103 --clip
median "ellipsoid 40 --clip" 0.5 $D/ellipsoid_2_1_1.stl --spheres 40 --resolution 103 --clip
median "torus 40 --clip" 1.0 $D/torus.stl --spheres 40 --resolution 103 --clip
median "femur 70 unbounded (--max-protrusion inf)" - $D/human_femur.stl --spheres 70 --resolution 103 --max-protrusion inf
echo
bash bench/load.sh
echo
/usr/bin/python3 bench/cost_growth.py
