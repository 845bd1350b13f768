#!/usr/bin/env bash
# Builds the Debian package of yade-mss: dist/yade-mss_VERSION_ARCH.deb, installed as YADE's users install things,
#   apt-get install ./dist/yade-mss_VERSION_amd64.deb     (beside Debian's yade; apt-get remove yade-mss undoes it)
# It holds the mss command (/usr/bin/mss), the C++ library, its public headers and its CMake and pkg-config files
# (/usr/lib, /usr/include/mss), and the Python package where Debian's python3 and YADE find it
# (/usr/lib/python3/dist-packages/yade_mss). Its dependencies are Debian's package names: those of the shared
# libraries it links (found as dpkg-shlibdeps finds them) and of the Python modules it imports; YADE, Dask and what
# a C++ code needs to build against the library (Eigen, CGAL, GMP, MPFR headers) are recommended, so that apt
# installs them unless told --no-install-recommends (the command and YADE's side need none of them).
#   bash scripts/package.sh            build, then check the package with lintian (an error fails the script)
# Needs the build's Debian packages (bash scripts/setup.sh main) and dpkg-dev, fakeroot and lintian.
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$(pwd)
for tool in dpkg-deb dpkg-shlibdeps fakeroot lintian; do
  command -v "$tool" > /dev/null || {
    echo "package: $tool is missing: apt-get install dpkg-dev fakeroot lintian" >&2; exit 1; }
done
VERSION=$(sed -n 's/^project(yade_mss VERSION \([0-9.]*\).*/\1/p' CMakeLists.txt)
[ -n "$VERSION" ] || { echo "package: no version in CMakeLists.txt's project()" >&2; exit 1; }
ARCH=$(dpkg --print-architecture)
PYDIR=lib/python3/dist-packages/yade_mss
t0=$(date +%s)

# a build of its own, installed under /usr into a staging root; the command linked dynamically, as Debian links
# (static, it embeds glibc's and GMP's copies, which lintian refuses; it starts about 8 ms slower: CMakeLists.txt)
cmake -S . -B build-deb -DCMAKE_BUILD_TYPE=Release -DCMAKE_INSTALL_PREFIX=/usr -DMSS_BUILD_TESTS=OFF \
  -DMSS_BUILD_BENCH=OFF -DMSS_STATIC_CLI=OFF -DMSS_PYTHON_INSTALL_DIR=$PYDIR > build-deb.log 2>&1 || { tail -30 build-deb.log; exit 1; }
cmake --build build-deb -j"$(nproc)" >> build-deb.log 2>&1 || { tail -50 build-deb.log; exit 1; }
STAGE=$(mktemp -d)
trap 'rm -rf "$STAGE"' EXIT
PKG=$STAGE/yade-mss
DESTDIR=$PKG cmake --install build-deb --strip >> build-deb.log 2>&1 || { tail -20 build-deb.log; exit 1; }
find "$PKG" -name __pycache__ -prune -exec rm -rf {} +

# the documents every Debian package carries: the copyright (the project has no licence yet: said so, none
# invented), a changelog of the package, the README
DOC=$PKG/usr/share/doc/yade-mss
mkdir -p "$DOC"
cat > "$DOC/copyright" << EOF
Format: https://www.debian.org/doc/packaging-manuals/copyright-format/1.0/
Upstream-Name: yade-mss
Source: the yade-mss repository

Files: *
Copyright: 2026 the yade-mss developers
License: not-chosen
 The yade-mss developers have not chosen a licence for the project yet (the repository declares none); until
 they do, no licence is granted here. The test data the repository bundles (not in this package) carry their
 own licences, listed in its tests/data/README.md.
EOF
cat > "$STAGE/changelog" << EOF
yade-mss ($VERSION) unstable; urgency=medium

  * Version $VERSION: see /usr/share/doc/yade-mss/CHANGELOG.md.gz.

 -- yade-mss developers <yade-mss@users.noreply.github.com>  $(date -R)
EOF
gzip -9n -c "$STAGE/changelog" > "$DOC/changelog.gz"  # a native package's name for it
gzip -9n -c CHANGELOG.md > "$DOC/CHANGELOG.md.gz"
cp README.md "$DOC/README.md"
# the command's manual page, from its own --help
mkdir -p "$PKG/usr/share/man/man1"
{
  echo '.TH MSS 1 "" "yade-mss '"$VERSION"'" "User Commands"'
  echo '.SH NAME'
  echo 'mss \- multi-sphere clumps of grains for DEM (YADE and other codes)'
  echo '.SH DESCRIPTION'
  echo '.nf'
  "$PKG/usr/bin/mss" --help 2>&1 | sed -e 's/\\/\\\\/g' -e 's/^\./\\\&./'
  echo '.fi'
  echo '.SH SEE ALSO'
  echo '/usr/share/doc/yade-mss/README.md'
} | gzip -9n > "$PKG/usr/share/man/man1/mss.1.gz"

# the dependencies: the packages of the shared libraries it links, then its Python modules' and YADE's
mkdir -p "$STAGE/src/debian"
printf 'Source: yade-mss\n\nPackage: yade-mss\nArchitecture: any\n' > "$STAGE/src/debian/control"
elves=$(find "$PKG" -type f \( -name '*.so' -o -path '*/bin/*' \) -exec sh -c 'file -b "$1" | grep -q "^ELF" && echo "$1"' _ {} \;)
# shellcheck disable=SC2086
shlibs=$(cd "$STAGE/src" && dpkg-shlibdeps -O $elves 2> "$STAGE/shlibdeps.log" | sed -n 's/^shlibs:Depends=//p')
PYDEPS="python3 (>= 3.11), python3 (<< 3.12), python3-numpy, python3-scipy, python3-matplotlib, python3-tqdm, \
python3-skimage, python3-tifffile"
mkdir -p "$PKG/DEBIAN"
cat > "$PKG/DEBIAN/control" << EOF
Package: yade-mss
Version: $VERSION
Architecture: $ARCH
Maintainer: yade-mss developers <yade-mss@users.noreply.github.com>
Installed-Size: $(du -sk --exclude=DEBIAN "$PKG" | cut -f1)
Depends: ${shlibs:+$shlibs, }$PYDEPS
Recommends: yade, python3-distributed, libeigen3-dev, libcgal-dev, libgmp-dev, libmpfr-dev
Section: science
Priority: optional
Description: multi-sphere clumps of real grains for DEM simulations
 yade-mss turns a grain's triangle mesh or voxel volume into a clump of
 overlapping spheres that matches its shape closely with few spheres (the MSS
 algorithm: spheres at the sub-voxel maxima of the Euclidean distance
 transform), with the grain's exact mass and inertia. It brings the mss
 command (generation, batches of CT scans, exports to other DEM codes,
 comparisons), a C++ library with CMake and pkg-config files, and the Python
 package yade_mss that builds YADE clumps.
EOF
mkdir -p dist
DEB=dist/yade-mss_${VERSION}_${ARCH}.deb
fakeroot dpkg-deb --build -Zxz "$PKG" "$DEB" > /dev/null
echo "package: built $DEB ($(du -h "$DEB" | cut -f1)) in $(( $(date +%s) - t0 )) s"
echo "package: Depends: $(sed -n 's/^Depends: //p' "$PKG/DEBIAN/control")"

# lintian: an error fails the build; its warnings are printed, counted and left for the note
set +e
lintian --no-tag-display-limit "$DEB" > "$ROOT/dist/lintian.txt" 2>&1
set -e
errors=$(grep -c '^E:' "$ROOT/dist/lintian.txt" || true)
warnings=$(grep -c '^W:' "$ROOT/dist/lintian.txt" || true)
echo "package: lintian: $errors errors, $warnings warnings (dist/lintian.txt)"
grep -E '^(E|W):' "$ROOT/dist/lintian.txt" | sed 's/^/  /' || true
[ "$errors" -eq 0 ] || { echo "package: lintian reports errors" >&2; exit 1; }
