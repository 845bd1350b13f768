#!/usr/bin/env bash
# Set-up, then every test:
#  1. ctest on the release build: C++ unit tests, CLI and bad-input corpus, Python (plain and inside real YADE),
#     the examples (short runs), replays of the fuzz corpus; then the manual (scripts/docs.sh); then the Debian
#     package (scripts/package.sh), installed, run and removed (tests/package/test_package.sh);
#  2. the C++ tests, CLI, corpus and fuzz replays again under AddressSanitizer + UndefinedBehaviorSanitizer;
#  3. every fuzz target (libFuzzer, clang) for MSS_FUZZ_SECONDS (default 45) each, from its seed corpus, inputs up
#     to 1 MB, with the format's words (fuzz/dict/) where there is a dictionary.
# MSS_QUICK=1 runs step 1 only.
set -euo pipefail
cd "$(dirname "$0")/.."
MSS_STRICT=${MSS_STRICT:-ON} bash scripts/setup.sh
(cd build && ctest --output-on-failure -j"$(nproc)")
echo "== the manual (Sphinx, warnings as errors; opened in headless Chromium)"
bash scripts/docs.sh
echo "== the Debian package: built (lintian: no error), installed with apt-get, the quickstart run from it, removed"
bash scripts/package.sh
bash tests/package/test_package.sh "dist/yade-mss_$(sed -n 's/^project(yade_mss VERSION \([0-9.]*\).*/\1/p' \
  CMakeLists.txt)_$(dpkg --print-architecture).deb"
[ "${MSS_QUICK:-0}" = "1" ] && exit 0

echo "== sanitizers (ASan + UBSan); not strict: GCC 12 reports false maybe-uninitialized warnings in libstdc++ under ASan"
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DMSS_SANITIZE=ON -DMSS_BUILD_PYTHON=OFF \
  -DMSS_BUILD_BENCH=OFF -DMSS_STRICT=OFF > build-asan.log 2>&1 || { tail -30 build-asan.log; exit 1; }
cmake --build build-asan -j"$(nproc)" >> build-asan.log 2>&1 || { tail -50 build-asan.log; exit 1; }
(cd build-asan && ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --output-on-failure -j"$(nproc)")

echo "== fuzzing (libFuzzer)"
cmake -S . -B build-fuzz -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo -DMSS_BUILD_FUZZ=ON \
  -DMSS_BUILD_TESTS=OFF -DMSS_BUILD_PYTHON=OFF -DMSS_BUILD_BENCH=OFF > build-fuzz.log 2>&1 || { tail -30 build-fuzz.log; exit 1; }
cmake --build build-fuzz -j"$(nproc)" >> build-fuzz.log 2>&1 || { tail -50 build-fuzz.log; exit 1; }
ROOT=$(pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
total=0
for t in stl obj off ply npy spheres generate; do
  mkdir -p "$work/$t"
  cp fuzz/corpus/$t/* "$work/$t/"
  dict=()
  [ -f "fuzz/dict/$t.dict" ] && dict=(-dict="$ROOT/fuzz/dict/$t.dict")
  (cd "$work" && "$ROOT/build-fuzz/fuzz_$t" -max_total_time="${MSS_FUZZ_SECONDS:-45}" -rss_limit_mb=2048 \
    "${dict[@]}" -max_len=1048576 -timeout=10 -print_final_stats=1 "$work/$t" > "$work/$t.log" 2>&1) || {
    echo "fuzz_$t found a problem:"; grep -E "ERROR|SUMMARY|runtime error|Test unit written" "$work/$t.log" | head
    mkdir -p fuzz/found && cp "$work"/crash-* "$work"/oom-* "$work"/timeout-* fuzz/found/ 2>/dev/null || true
    echo "the inputs are in fuzz/found: add them to fuzz/regressions/$t and fix"; exit 1; }
  runs=$(awk '/stat::number_of_executed_units/{print $2}' "$work/$t.log")
  total=$((total + runs))
  echo "fuzz_$t: $runs executions, no crash"
done
echo "fuzzing: $total executions in all, no crash"
