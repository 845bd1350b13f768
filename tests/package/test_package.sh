#!/usr/bin/env bash
# The Debian package as a user meets it: apt-get installs dist/yade-mss_*.deb beside Debian's yade, the quickstart
# runs from what it installed (the mss command in /usr/bin, the yade_mss package in Debian's python3 and YADE),
# `mss --version` and yade_mss.__version__ agree with it, and apt-get remove leaves none of its files behind.
#   bash tests/package/test_package.sh dist/yade-mss_VERSION_ARCH.deb
set -euo pipefail
cd "$(dirname "$0")/../.."
DEB=$(realpath "$1")
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
VERSION=$(dpkg-deb -f "$DEB" Version)
fail() { echo "package test: $*" >&2; exit 1; }
files=$(dpkg-deb -c "$DEB" | awk '{print $6}' | sed 's|^\./|/|' | grep -v '/$')
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq "$DEB" > /dev/null 2>&1 || fail "apt-get install failed"
trap 'DEBIAN_FRONTEND=noninteractive $SUDO apt-get remove -y -qq yade-mss > /dev/null 2>&1 || true' EXIT
dpkg-query -W -f='${Status} ${Version}\n' yade-mss | grep -qx "install ok installed $VERSION" || fail "not installed"
for f in $files; do [ -e "$f" ] || fail "$f is not installed"; done
[ "$(/usr/bin/mss --version)" = "mss (yade-mss) $VERSION" ] || fail "/usr/bin/mss --version says '$(/usr/bin/mss --version)'"
# the installed package first, before any other copy (a source install in /usr/local)
export PYTHONPATH=/usr/lib/python3/dist-packages
got=$(/usr/bin/python3 -c 'import yade_mss; print(yade_mss.__version__, yade_mss.__file__)')
[ "$got" = "$VERSION /usr/lib/python3/dist-packages/yade_mss/__init__.py" ] || fail "yade_mss is '$got'"
work=$(mktemp -d)
cp examples/quickstart.py "$work/"
mkdir -p "$work/tests/data" && cp tests/data/human_femur.stl "$work/tests/data/"
(cd "$work" && yade -n -x quickstart.py > quickstart.log 2>&1) || { tail -20 "$work/quickstart.log"; fail "the quickstart failed"; }
grep -q "yade_mss/__init__" "$work/quickstart.log" && fail "a traceback from yade_mss"
/usr/bin/mss generate "$work/tests/data/human_femur.stl" --spheres 20 -o "$work/f.csv" > /dev/null
[ "$(tail -n +2 "$work/f.csv" | wc -l)" -eq 20 ] || fail "mss generate did not write 20 spheres"
/usr/bin/mss preview "$work/tests/data/human_femur.stl" "$work/f.csv" -o "$work/f.png" > /dev/null  # its Python
[ -s "$work/f.png" ] || fail "mss preview (the Python side of the command) wrote no picture"
# the C++ library as another DEM code links it: found through the installed CMake package and pkg-config (in
# /usr only: not a source install's copy in /usr/local)
cmake -S examples/cpp -B "$work/cpp" -DCMAKE_PREFIX_PATH=/usr -DCMAKE_FIND_USE_CMAKE_SYSTEM_PATH=OFF \
  > "$work/cpp.log" 2>&1 && cmake --build "$work/cpp" >> "$work/cpp.log" 2>&1 || { tail -20 "$work/cpp.log"; fail "examples/cpp does not build against the package"; }
grep -q "/usr/lib/cmake/mss" "$work/cpp/CMakeCache.txt" || fail "find_package(mss) did not find the package's"
[ "$("$work/cpp/grain_to_spheres" tests/data/human_femur.stl 20 2000 | grep -c '^sphere ')" -eq 20 ] ||
  fail "the consumer built against the package did not give 20 spheres"
PC=/usr/lib/pkgconfig:/usr/share/pkgconfig:/usr/lib/$(dpkg-architecture -qDEB_HOST_MULTIARCH)/pkgconfig
[ "$(PKG_CONFIG_LIBDIR=$PC pkg-config --modversion mss)" = "$VERSION" ] || fail "pkg-config's mss"
rm -rf "$work"
DEBIAN_FRONTEND=noninteractive $SUDO apt-get remove -y -qq yade-mss > /dev/null
trap - EXIT
dpkg-query -W -f='${Status}\n' yade-mss 2>/dev/null | grep -q "^install ok" && fail "still installed after remove"
for f in $files; do
  case "$f" in /usr/share/doc/*) continue ;; esac  # apt-get remove keeps nothing else of ours
  [ -e "$f" ] && fail "$f is left after apt-get remove"
done
[ -d /usr/lib/python3/dist-packages/yade_mss ] && fail "the yade_mss folder is left after apt-get remove"
echo "package test: $(basename "$DEB") installed, ran the quickstart, mss --version and yade_mss.__version__ $VERSION, removed cleanly"
