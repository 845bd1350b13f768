#!/usr/bin/env bash
# Runs every case of cases.tsv through the mss command line and sorts each outcome as the corpus's classes:
# clean (as expected), crash (a signal: exit >= 128, or an exit status that is neither 0 nor 1), hang (60 s),
# silent (exit 0 where an error was expected), unclear (an error without the expected fragment, an output file
# left behind, or a valid file refused). Prints the counts; passes only when every case is clean.
# usage: run_corpus.sh MSS DATA_DIR
set -u
MSS=$1
DATA=$2
HERE=$(cd "$(dirname "$0")" && pwd)
TMP=$(mktemp -d)
SPECIAL=$(mktemp -d)
trap 'rm -rf "$TMP" "$SPECIAL"' EXIT
mkfifo "$SPECIAL/grain.stl" "$SPECIAL/grain.npy" "$SPECIAL/spheres.csv"
declare -A count=([clean]=0 [crash]=0 [hang]=0 [silent]=0 [unclear]=0)
while IFS=$'\t' read -r name args fragment; do
  [[ -z "$name" || "$name" == \#* ]] && continue
  args=${args//\{C\}/$HERE/files}
  args=${args//\{D\}/$DATA}
  args=${args//\{T\}/$TMP}
  args=${args//\{F\}/$SPECIAL}
  want_ok=0
  if [[ "$fragment" == ok:* ]]; then want_ok=1; fragment=${fragment#ok:}; fi
  # shellcheck disable=SC2086
  out=$(timeout 60 "$MSS" $args 2>&1 </dev/null)
  rc=$?
  if [ $rc -eq 124 ]; then class=hang
  elif [ $rc -ne 0 ] && [ $rc -ne 1 ]; then class=crash
  elif [ $want_ok -eq 1 ]; then
    if [ $rc -eq 0 ] && grep -qF -- "$fragment" <<<"$out"; then class=clean; else class=unclear; fi
  elif [ $rc -eq 0 ]; then class=silent
  elif grep -qF -- "$fragment" <<<"$out" && [ -z "$(ls -A "$TMP")" ]; then class=clean
  else class=unclear; fi
  count[$class]=$((count[$class] + 1))
  [ $class = clean ] || echo "$class: $name (exit $rc, expected '$fragment'): $out"
  rm -rf "${TMP:?}"/*
done < "$HERE/cases.tsv"
total=0
for c in clean crash hang silent unclear; do total=$((total + count[$c])); done
echo "corpus: $total cases: ${count[clean]} clean, ${count[crash]} crash, ${count[hang]} hang, ${count[silent]} silent, ${count[unclear]} unclear"
[ "${count[clean]}" -eq "$total" ] && [ "$total" -ge 25 ]
