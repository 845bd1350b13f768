#!/usr/bin/env bash
# Runs every case of cases.tsv through the mss command line: exit status 1 (no crash: a signal gives >= 128;
# no hang: 60 s), the expected fragment in the message, no output file left.
# usage: run_corpus.sh MSS DATA_DIR
set -u
MSS=$1
DATA=$2
HERE=$(cd "$(dirname "$0")" && pwd)
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
pass=0
fail=0
while IFS=$'\t' read -r name args fragment; do
  [[ -z "$name" || "$name" == \#* ]] && continue
  args=${args//\{C\}/$HERE/files}
  args=${args//\{D\}/$DATA}
  args=${args//\{T\}/$TMP}
  # shellcheck disable=SC2086
  out=$(timeout 60 "$MSS" $args 2>&1)
  rc=$?
  if [ $rc -eq 1 ] && grep -qF -- "$fragment" <<<"$out" && [ -z "$(ls -A "$TMP")" ]; then
    pass=$((pass + 1))
  else
    fail=$((fail + 1))
    echo "FAILED: $name (exit $rc, expected '$fragment'): $out"
  fi
  rm -rf "${TMP:?}"/*
done < "$HERE/cases.tsv"
echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ] && [ "$pass" -ge 25 ]
