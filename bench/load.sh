#!/usr/bin/env bash
# Generation when the cores are shared: femur 70 spheres with 3 busy processes on the machine: 1 thread, 2
# threads with spinning OpenMP waits (--threads 2, OMP_WAIT_POLICY=active), the command's default (when the
# cores are busy as it starts, as here, passive waiting on as many threads as cores are free, at least one; a
# short spin when each thread finds a free core),
# and the library's default where the waiting policy is active (dynamic team sizes: what a C++ program or
# YADE that started OpenMP first gets).
# Prints each run's five times, sorted. usage: bash bench/load.sh   (after bash scripts/setup.sh)
set -euo pipefail
cd "$(dirname "$0")/.."
MSS=./build/mss
pids=()
for i in 1 2 3; do (while :; do :; done) & pids+=($!); done
trap 'kill "${pids[@]}" 2>/dev/null' EXIT
sleep 1
echo "load: $(cut -d' ' -f1 /proc/loadavg) (3 busy processes on $(nproc) cores)"
for cfg in "--threads 1" "--threads 2 OMP_WAIT_POLICY=active" "default" "OMP_WAIT_POLICY=active"; do
  ts=""
  opt=() envs=()
  for w in $cfg; do
    case $w in --threads) opt+=(--threads) ;; [0-9]*) opt+=("$w") ;; *=*) envs+=("$w") ;; esac
  done
  for k in 1 2 3 4 5; do
    s=$(date +%s.%N)
    env "${envs[@]}" $MSS generate tests/data/human_femur.stl --spheres 70 --resolution 103 "${opt[@]}" \
      -o /tmp/mss_load.txt > /dev/null
    e=$(date +%s.%N)
    ts="$ts $(echo "$e - $s" | bc)"
  done
  echo "$cfg: $(echo $ts | tr ' ' '\n' | sort -n | tr '\n' ' ')"
done
