#!/usr/bin/env bash
# Installs what yade-mss needs from Debian 12 (bookworm) packages and builds it into build/.
#   bash scripts/setup.sh main   what the main job needs (scripts/demo.sh): the build, YADE, the pictures
#   bash scripts/setup.sh        everything (scripts/test.sh): also the tests, the manual, the exports' codes
# Safe to run again: installed packages are skipped, the build is incremental.
set -euo pipefail
cd "$(dirname "$0")/.."
PROFILE=${1:-all}
case "$PROFILE" in main | all) ;; *) echo "setup: unknown profile '$PROFILE' (main or all)" >&2; exit 2 ;; esac

# the library, the mss command, the Python package inside YADE, and its pictures
MAIN=(build-essential cmake pkgconf libcgal-dev libeigen3-dev libboost-dev libgmp-dev libmpfr-dev libcli11-dev
      libboost-python-dev python3-dev python3-numpy python3-matplotlib python3-tqdm yade)
# the tests (Google Test and Benchmark, Hypothesis), batches (SciPy, scikit-image, Dask, TIFF stacks), the manual
# (Sphinx, Breathe, Doxygen, opened in Chromium), the exports read by the real codes (LIGGGHTS, VTK), the fuzz
# targets (clang, its libFuzzer runtime and OpenMP), the Debian package (dpkg-dev, fakeroot, lintian)
REST=(libgtest-dev libbenchmark-dev python3-scipy python3-skimage python3-distributed python3-tifffile
      python3-hypothesis chromium python3-sphinx python3-breathe doxygen python3-vtk9 liggghts
      clang libclang-rt-14-dev libomp-14-dev dpkg-dev fakeroot lintian file)
PACKAGES=("${MAIN[@]}")
[ "$PROFILE" = all ] && PACKAGES+=("${REST[@]}")
missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}"
  SUDO=""
  [ "$(id -u)" -eq 0 ] || SUDO="sudo"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq "${missing[@]}" > /dev/null
fi

BUILD_TYPE=${MSS_BUILD_TYPE:-Release}
WITH_TESTS=ON
[ "$PROFILE" = main ] && WITH_TESTS=OFF  # no Google Test or Benchmark: the library, mss and yade_mss alone
cmake -S . -B build -DCMAKE_BUILD_TYPE="$BUILD_TYPE" -DMSS_STRICT=${MSS_STRICT:-OFF} -DMSS_BUILD_TESTS=$WITH_TESTS \
  -DMSS_BUILD_BENCH=$WITH_TESTS > build.log 2>&1 || { cat build.log; exit 1; }
cmake --build build -j"$(nproc)" >> build.log 2>&1 || { tail -50 build.log; exit 1; }
# install mss (/usr/local/bin) and the yade_mss package where Debian's python3, and so yade, finds it
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
$SUDO cmake --install build >> build.log 2>&1 || { tail -20 build.log; exit 1; }
echo "setup: built and installed mss and yade_mss ($PROFILE)"
