#!/usr/bin/env bash
# The library as another DEM code uses it: this build installed into a folder of the test's own, then
# examples/cpp built against the installation, once with find_package(mss) (target mss::mss) and once with
# pkg-config, and run on a real mesh: its spheres, and the grain's mass as `mss info` measures the volume.
# usage: test_consumer.sh BUILD_DIR SOURCE_DIR MSS_BINARY
set -u
BUILD=$1
SRC=$2
MSS=$3
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
fail=0
ok() { echo "ok: $1"; }
bad() { echo "FAILED: $1"; fail=1; }
cmake --install "$BUILD" --prefix "$TMP/prefix" > "$TMP/install.log" 2>&1 || { cat "$TMP/install.log"; exit 1; }
# only the public headers: the table of contents and what it includes, nothing of the internals
[ -f "$TMP/prefix/include/mss.hpp" ] && ok "include/mss.hpp installed" || bad "include/mss.hpp missing"
# exactly the headers mss.hpp lists, each compiling on its own against the installation (no internal one needed)
listed=$(grep -o '"mss/[a-z_]*\.hpp"' "$SRC/pkg/mss.hpp" | tr -d '"' | sort)
installed=$(cd "$TMP/prefix/include" && find mss -type f | sort)
[ "$listed" = "$installed" ] && ok "installed headers are the $(wc -l <<<"$listed") public ones" ||
  bad "installed headers differ from mss.hpp's list: $(diff <(echo "$listed") <(echo "$installed") | tr '\n' ' ')"
for h in $installed; do
  echo "#include <$h>" > "$TMP/one.cpp"
  c++ -std=c++17 -fsyntax-only -I"$TMP/prefix/include" -I/usr/include/eigen3 "$TMP/one.cpp" 2> "$TMP/one.log" &&
    ok "$h compiles alone" || bad "$h does not compile alone: $(head -3 "$TMP/one.log")"
done
cmake -S "$SRC/examples/cpp" -B "$TMP/cmake-build" -DCMAKE_PREFIX_PATH="$TMP/prefix" > "$TMP/cfg.log" 2>&1 &&
  cmake --build "$TMP/cmake-build" > "$TMP/build.log" 2>&1 || { cat "$TMP/cfg.log" "$TMP/build.log"; exit 1; }
PKG_CONFIG_PATH="$TMP/prefix/lib/pkgconfig" pkg-config --exists mss || { echo "pkg-config finds no mss"; exit 1; }
# shellcheck disable=SC2046
c++ -std=c++17 -O1 "$SRC/examples/cpp/grain_to_spheres.cpp" -o "$TMP/pc_consumer" \
  $(PKG_CONFIG_PATH="$TMP/prefix/lib/pkgconfig" pkg-config --cflags --libs --static mss) 2> "$TMP/pc.log" ||
  { cat "$TMP/pc.log"; exit 1; }
volume=$("$MSS" info "$SRC/tests/data/human_femur.stl" | awk '$1 == "volume" {print $2}')
for exe in "$TMP/cmake-build/grain_to_spheres" "$TMP/pc_consumer"; do
  out=$("$exe" "$SRC/tests/data/human_femur.stl" 20 2000) || { bad "$exe failed: $out"; continue; }
  n=$(grep -c '^sphere ' <<<"$out")
  [ "$n" -eq 20 ] && ok "$(basename "$exe"): 20 spheres" || bad "$(basename "$exe"): $n spheres, not 20"
  mass=$(awk '$1 == "mass" {print $2}' <<<"$out")
  awk -v m="$mass" -v v="$volume" 'BEGIN { exit !(v > 0 && (m / (2000 * v) - 1) ^ 2 < 1e-12) }' &&
    ok "$(basename "$exe"): mass $mass = 2000 x volume $volume" || bad "$(basename "$exe"): mass $mass vs 2000 x $volume"
  awk '$1 == "sphere" && !($5 > 0) {exit 1}' <<<"$out" && ok "radii positive" || bad "a radius <= 0"
done
"$TMP/cmake-build/grain_to_spheres" "$SRC/tests/data/missing.stl" 3 1 2> "$TMP/err.txt"
[ $? -eq 1 ] && grep -q "cannot open" "$TMP/err.txt" && ok "a missing mesh: exit 1, 'cannot open'" ||
  bad "a missing mesh: $(cat "$TMP/err.txt")"
exit $fail
