#!/usr/bin/env bash
# The speed figures in one run: end-to-end times (the command's whole run, process start and
# exit included; median of 5 after an untimed run, 2 threads; beside them the time mss reports, STL read to
# spheres written) against their targets, generation under load
# (bench/load.sh), and how cost grows with grid size and sphere count (bench/cost_growth.py). The machine's
# load is printed first; each end-to-end median is also a row of bench/results/speed.csv.
# usage: bash bench/speed.sh   (after bash scripts/setup.sh)
set -euo pipefail
cd "$(dirname "$0")/.."
MSS=./build/mss
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT
source bench/lib.sh
echo "load: $(cat /proc/loadavg)"
median() { # label target args...: median of 5 end-to-end times, after one untimed run
  local label=$1 target=$2
  shift 2
  local ts=() own=() s e
  # the first run after an idle spell was 20-30% slower on this VM (femur 70: 0.157-0.163 s, then
  # 0.122-0.135 s): its cores wake slowly; the untimed run also reads the mesh into the page cache
  $MSS generate "$@" --threads 2 -o "$OUT/s.csv" > /dev/null
  for _ in 1 2 3 4 5; do
    # the command's whole life, process start and exit included (EPOCHREALTIME: no process is started to
    # read the clock), and the time it reports itself, from reading the mesh to the spheres written
    s=$EPOCHREALTIME
    $MSS generate "$@" --threads 2 -o "$OUT/s.csv" > "$OUT/run.log"
    e=$EPOCHREALTIME
    ts+=("$(awk -v s="$s" -v e="$e" 'BEGIN{printf "%.4f", e - s}')")
    own+=("$(awk '/^seconds/{print $NF}' "$OUT/run.log")")
  done
  printf '%-34s median %6.3f s   target %5s s   (runs: %s; in-process median %.3f s)\n' "$label" \
    "$(printf '%s\n' "${ts[@]}" | sort -g | sed -n 3p)" "$target" "${ts[*]}" \
    "$(printf '%s\n' "${own[@]}" | sort -g | sed -n 3p)"
  bench_row speed.csv case,median_s,target_s,in_process_median_s "$label" \
    "$(printf '%s\n' "${ts[@]}" | sort -g | sed -n 3p)" "$target" "$(printf '%s\n' "${own[@]}" | sort -g | sed -n 3p)"
}
D=tests/data
median "femur 70, resolution 103" 0.12 $D/human_femur.stl --spheres 70 --resolution 103
median "ellipsoid 10, resolution 103" 0.08 $D/ellipsoid_2_1_1.stl --spheres 10 --resolution 103
median "femur 70, resolution 205" 0.7 $D/human_femur.stl --spheres 70 --resolution 205
median "femur 70 --clip" 0.25 $D/human_femur.stl --spheres 70 --resolution 103 --clip
median "ellipsoid 40 --clip" 0.5 $D/ellipsoid_2_1_1.stl --spheres 40 --resolution 103 --clip
median "torus 40 --clip" 1.0 $D/torus.stl --spheres 40 --resolution 103 --clip
median "femur 70 unbounded (--max-protrusion inf)" - $D/human_femur.stl --spheres 70 --resolution 103 --max-protrusion inf
# the joint polish (opt-in): what it would cost as the default method's last stage, against the first two targets
median "femur 70 --polish" - $D/human_femur.stl --spheres 70 --resolution 103 --polish
median "ellipsoid 10 --polish" - $D/ellipsoid_2_1_1.stl --spheres 10 --resolution 103 --polish
echo
# What a second thread buys on this machine: femur 70 on one thread and on two, alternating, each phase's
# median of 5. On the 2-core VM of these figures two busy threads each ran 25-40% slower than one alone (the
# refinement's trial loops: 55-58 ms of work on one thread, 69-77 ms summed over two), so the phases that
# compute rather than stream speed up 1.3x, not 2x: the end-to-end targets are near what the hardware allows.
for _ in 1 2 3 4 5; do
  for t in 1 2; do
    $MSS generate $D/human_femur.stl --spheres 70 --resolution 103 --threads $t -o "$OUT/s.csv" |
      awk -v t=$t '/^seconds/{print t, $3, $5, $7, $9, $11, $13}' >> "$OUT/threads.log"
  done
done
col() { awk -v t="$1" -v c="$2" '$1 == t {print $c}' "$OUT/threads.log" | sort -g | sed -n 3p; }
printf '%-34s %8s %8s %8s %8s %8s %8s\n' "threads: femur 70, phase medians" read voxelize edt select refine total
for t in 1 2; do
  printf '%-34s' "  $t thread(s), seconds"
  for c in 2 3 4 5 6 7; do printf ' %8.4f' "$(col $t $c)"; done
  echo
done
printf '%-34s' "  one thread / two"
for c in 2 3 4 5 6 7; do printf ' %8.2f' "$(awk -v a="$(col 1 $c)" -v b="$(col 2 $c)" 'BEGIN{print a / b}')"; done
echo
echo
bash bench/load.sh
echo
/usr/bin/python3 bench/cost_growth.py
