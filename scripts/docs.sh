#!/usr/bin/env bash
# Builds the manual into build/docs/html (Sphinx; every warning is an error): the command-line reference from
# the option table and the results tables from bench/results (docs/gen_reference.py, into docs/_generated), the
# gallery (docs/make_gallery.py: the examples run in YADE, into docs/_gallery), the
# C++ API from the public headers (doxygen XML, through breathe), the Python API from the docstrings.
# Then opens it in headless Chromium and checks what a reader sees. Needs a build (bash scripts/setup.sh).
# usage: bash scripts/docs.sh
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${MSS_BUILD_DIR:-build}
PY=/usr/bin/python3
[ -f "$BUILD/py/yade_mss/_mss.so" ] || { echo "docs: no build in $BUILD: run bash scripts/setup.sh first" >&2; exit 1; }
PYTHONPATH=$BUILD/py $PY docs/gen_reference.py docs/_generated
# the gallery: every example run in YADE (short runs) and a batch's report, pages made from what they print and draw
PYTHONPATH=$(realpath "$BUILD/py") MSS_BINARY=$(realpath "$BUILD/mss") $PY docs/make_gallery.py docs/_gallery
$PY docs/gen_reference.py --check-readme README.md   # its figures are the newest bench rows, not typed
PYTHONPATH=$BUILD/py $PY docs/make_figure.py --check   # the front picture's figures are this build's
XML=$BUILD/docs-xml
rm -rf "$XML"
mkdir -p "$XML"
doxygen - > "$BUILD/doxygen.log" 2>&1 <<DOXY || { tail -20 "$BUILD/doxygen.log"; exit 1; }
PROJECT_NAME = mss
INPUT = pkg/mss/generate.hpp pkg/mss/options.hpp pkg/mss/score.hpp pkg/mss/compare.hpp pkg/mss/mass.hpp pkg/mss/io.hpp pkg/mss/planes.hpp pkg/mss/surface.hpp
GENERATE_XML = YES
GENERATE_HTML = NO
GENERATE_LATEX = NO
XML_OUTPUT = .
OUTPUT_DIRECTORY = $XML
EXTRACT_ALL = YES
QUIET = YES
WARN_IF_UNDOCUMENTED = NO
DOXY
rm -rf "$BUILD/docs"
PYTHONPATH=$BUILD/py MSS_DOXYGEN_XML=$(realpath "$XML") $PY -m sphinx -W --keep-going -q -b html docs "$BUILD/docs/html" \
  -d "$BUILD/docs/doctrees"
# what a reader sees, in a real browser: the pages load, the reference lists the table's options
profile=$(mktemp -d)
trap 'rm -rf "$profile"' EXIT
page() {
  chromium --headless --no-sandbox --disable-gpu --no-first-run --disable-background-networking \
    --disable-component-update --disable-sync --user-data-dir="$profile" --virtual-time-budget=3000 \
    --dump-dom "file://$(realpath "$BUILD/docs/html/$1")" 2> /dev/null
}
fail=0
expect() { # page text
  if ! page "$1" | grep -qF -- "$2"; then echo "docs: $1 does not show '$2'" >&2; fail=1; fi
}
expect index.html "multi-sphere shape generator"
expect api/cli.html "--max-protrusion"
expect api/python.html "nSpheres"
expect api/cpp.html "settingsFrom"
expect api/cpp.html "unionSurface"
expect guide/surface.html "317,440"
expect results.html "femur 70"
expect guide/architecture.html "check_imports.py"
expect api/cli.html "--inertial-number"
expect tutorials/triaxial.html "What the sphere count does"
expect guide/export.html "_static/custom.css"   # code wraps, never clipped
expect _gallery/index.html "The report of a batch"
for ex in quickstart ct_specimen triaxial compare_clump crush_grain oedometer_crushing batch_report; do
  expect _gallery/$ex.html "${ex}_1.png"   # each page shows its pictures
done
[ $fail -eq 0 ] || exit 1
echo "docs: $BUILD/docs/html/index.html"
