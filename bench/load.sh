#!/usr/bin/env bash
# The command's default thread count, idle and when the cores are shared: femur 70 spheres, first on an idle
# machine (the default against --threads 1 and --threads 2), then with 3 busy processes on the machine
# (--threads 1, 2 threads with spinning OpenMP waits, the default, and the library's default where the waiting
# policy is active: dynamic team sizes, what a C++ program or YADE that started OpenMP first gets).
# The default: when every thread finds a free core as it starts, a short spin (GOMP_SPINCOUNT 10000) on as many
# threads as cores; when the cores are busy, passive waiting on as many threads as cores are free, at least one.
# Targets (issue 56): idle, the default within 1.1x of the best explicit --threads; busy, within 1.5x of
# --threads 1. Prints each configuration's five times, sorted, and the medians' ratios; appends a row a
# configuration to bench/results/load.csv. usage: bash bench/load.sh   (after bash scripts/setup.sh; idle machine)
set -euo pipefail
cd "$(dirname "$0")/.."
. bench/lib.sh
MSS=./build/mss
declare -A median

run() { # name, config words
  local name=$1 ts="" opt=() envs=() w s e k sorted
  shift
  for w in "$@"; do
    case $w in --threads) opt+=(--threads) ;; [0-9]*) opt+=("$w") ;; *=*) envs+=("$w") ;; esac
  done
  for k in 1 2 3 4 5; do
    s=$(date +%s.%N)
    env "${envs[@]}" $MSS generate tests/data/human_femur.stl --spheres 70 --resolution 103 "${opt[@]}" \
      -o /tmp/mss_load.txt > /dev/null
    e=$(date +%s.%N)
    ts="$ts $(echo "$e - $s" | bc)"
  done
  sorted=$(echo $ts | tr ' ' '\n' | sort -n | tr '\n' ' ')
  median[$name]=$(echo $sorted | cut -d' ' -f3)
  echo "$name: $sorted"
  BENCH_META="$(date -u +%Y-%m-%dT%H:%M:%S),$(git rev-parse --short HEAD 2>/dev/null || echo unknown),$(bench_machine),$(cut -d' ' -f1 /proc/loadavg)"
  bench_row load.csv "case,config,median_s,times_s" "${name%% *}" "${name#* }" "${median[$name]}" "$sorted"
}

echo "idle: load $(cut -d' ' -f1 /proc/loadavg), procs_running $(awk '/procs_running/{print $2}' /proc/stat)"
run "idle --threads 1" --threads 1
run "idle --threads 2" --threads 2
run "idle default" X=1
best=$(echo "${median[idle --threads 1]} ${median[idle --threads 2]}" | tr ' ' '\n' | sort -n | head -1)
echo "idle: the default's median over the best explicit: $(echo "scale=3; ${median[idle default]} / $best" | bc) (target 1.1)"

pids=()
for i in 1 2 3; do (while :; do :; done) & pids+=($!); done
trap 'kill "${pids[@]}" 2>/dev/null' EXIT
sleep 1
echo "busy: load $(cut -d' ' -f1 /proc/loadavg) (3 busy processes on $(nproc) cores)"
run "busy --threads 1" --threads 1
run "busy --threads 2 OMP_WAIT_POLICY=active" --threads 2 OMP_WAIT_POLICY=active
run "busy default" X=1
run "busy OMP_WAIT_POLICY=active" OMP_WAIT_POLICY=active
echo "busy: the default's median over --threads 1: $(echo "scale=3; ${median[busy default]} / ${median[busy --threads 1]}" | bc) (target 1.5)"
