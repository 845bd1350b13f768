#!/usr/bin/env bash
# Runs the breakage examples in full and puts its pictures in docs/ (the manual's breakage page):
# examples/crush_grain.py (one pebble between platens) and examples/oedometer_crushing.py (one-dimensional
# compression of 150 crushable grains). Prints their figures.
# usage: bash scripts/breakage_figures.sh   (after bash scripts/setup.sh)
set -euo pipefail
cd "$(dirname "$0")/.."
export PYTHONPATH=$PWD/build/py MSS_DATA=$PWD/tests/data MSS_FIGURES=$PWD/docs
for ex in crush_grain oedometer_crushing; do
  yade -n -x examples/$ex.py 2>&1 | grep -v -e '^Welcome to Yade' -e '^TCP python prompt' -e '^XMLRPC info' -e '^Using python'
done
