#!/usr/bin/env bash
# End-to-end tests of the mss command line: real files written and read back, errors with non-zero exit.
# usage: test_cli.sh MSS_BINARY DATA_DIR
set -u
MSS=$1
DATA=$2
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
pass=0
fail=0
check() { # name, condition-command...
  local name=$1
  shift
  if "$@"; then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAILED: $name"; fi
}
expect_error() { # name, fragment, command...
  local name=$1 fragment=$2
  shift 2
  local out rc
  out=$("$@" 2>&1)
  rc=$?
  if [ $rc -ne 0 ] && grep -q -- "$fragment" <<<"$out"; then pass=$((pass + 1)); else
    fail=$((fail + 1)); echo "FAILED: $name (rc=$rc, output: $out)"; fi
}

# generate: the three output formats, with the requested number of spheres
"$MSS" generate "$DATA/ellipsoid_2_1_1.stl" --spheres 6 --resolution 40 -o "$TMP/e.csv" > "$TMP/gen.log"
check "csv has header and 6 rows" [ "$(wc -l < "$TMP/e.csv")" -eq 7 ]
check "generate prints dice" grep -q '^dice' "$TMP/gen.log"
"$MSS" generate "$DATA/ellipsoid_2_1_1.stl" --spheres 6 --resolution 40 -o "$TMP/e.txt" > /dev/null
check "yade text has 6 clump rows of 5 columns" [ "$(grep -v '^#' "$TMP/e.txt" | awk 'NF==5' | wc -l)" -eq 6 ]
"$MSS" generate "$DATA/ellipsoid_2_1_1.stl" --spheres 6 --resolution 40 -o "$TMP/e.vtk" > /dev/null
check "vtk has 6 points" grep -q 'POINTS 6 double' "$TMP/e.vtk"
"$MSS" generate "$DATA/ellipsoid_2_1_1.stl" --eta 0.1 --resolution 40 --method paper -o "$TMP/p.csv" > "$TMP/p.log"
check "paper mode meets eta or stops" grep -q '^eta' "$TMP/p.log"

# clipping and planes: nothing outside the grain, nothing across the plane
"$MSS" generate "$DATA/human_femur.stl" --spheres 15 --resolution 30 --clip -o "$TMP/clip.csv" > /dev/null
"$MSS" compare "$DATA/human_femur.stl" "$TMP/clip.csv" --resolution 40 > "$TMP/clip.log"
check "clipped spheres have nothing outside" grep -qE '^outside +0$' "$TMP/clip.log"
# the protrusion bound: one voxel by default, as given, inf = unbounded; printed, and measured by compare
"$MSS" generate "$DATA/human_femur.stl" --spheres 15 --resolution 30 -o "$TMP/b1.csv" > "$TMP/b1.log"
h=$(awk '/^grid/{print $NF}' "$TMP/b1.log")
p=$(awk '/^protrusion/{print $2}' "$TMP/b1.log")
pc=$("$MSS" compare "$DATA/human_femur.stl" "$TMP/b1.csv" --resolution 40 | awk '/^protrusion/{print $2}')
check "default: protrusion $p (compare: $pc) <= one voxel $h" \
  awk -v p="$p" -v c="$pc" -v h="$h" 'BEGIN{exit !(p > 0 && p <= h * 1.000001 && c <= h * 1.000001)}'
"$MSS" generate "$DATA/human_femur.stl" --spheres 15 --resolution 30 --max-protrusion inf -o "$TMP/binf.csv" > "$TMP/binf.log"
check "--max-protrusion inf: unbounded, more than a voxel" \
  awk -v h="$h" '/^protrusion/{found = 1; if ($2 > 1.3 * h && $NF == "inf)") ok = 1} END{exit !(found && ok)}' "$TMP/binf.log"
"$MSS" generate "$DATA/human_femur.stl" --spheres 15 --resolution 30 --max-protrusion 0.5 -o "$TMP/b05.csv" > "$TMP/b05.log"
check "--max-protrusion 0.5 world units" awk '/^protrusion/{exit !($2 <= 0.5 * 1.000001)}' "$TMP/b05.log"
expect_error "negative bound" "--max-protrusion must be >= 0" "$MSS" generate "$DATA/human_femur.stl" --spheres 3 --max-protrusion -1 -o "$TMP/x.csv"
expect_error "--clip with a bound" "clip means maxProtrusion 0" "$MSS" generate "$DATA/human_femur.stl" --spheres 3 --clip --max-protrusion 2 -o "$TMP/x.csv"
"$MSS" generate "$DATA/human_femur.stl" --spheres 15 --resolution 30 --plane 0,0,-90,0,0,1 -o "$TMP/plane.csv" > /dev/null
check "no sphere crosses the plane z = -90" awk -F, 'NR > 1 && $3 - $4 < -90 - 1e-9 {bad = 1} END {exit bad}' "$TMP/plane.csv"
d_frag=$("$MSS" compare "$DATA/human_femur.stl" "$TMP/plane.csv" --plane 0,0,-90,0,0,1 | awk '/^dice/{print $2}')
d_whole=$("$MSS" compare "$DATA/human_femur.stl" "$TMP/plane.csv" | awk '/^dice/{print $2}')
check "compare --plane scores the fragment ($d_frag), not the whole grain ($d_whole)" \
  awk -v a="$d_frag" -v b="$d_whole" 'BEGIN{exit !(a < 0.15 && b > 0.2)}'
expect_error "bad plane in compare" "is not PX,PY,PZ,NX,NY,NZ" "$MSS" compare "$DATA/human_femur.stl" "$TMP/plane.csv" --plane 0,0,1
expect_error "zero plane normal in compare" "non-zero normal" "$MSS" compare "$DATA/human_femur.stl" "$TMP/plane.csv" --plane 0,0,0,0,0,0
expect_error "bad plane" "is not PX,PY,PZ,NX,NY,NZ" "$MSS" generate "$DATA/human_femur.stl" --spheres 3 --plane 1,2,3 -o "$TMP/x.csv"
"$MSS" generate "$DATA/stanford_bunny_open.stl" --spheres 5 --resolution 30 -o "$TMP/bunny.csv" > /dev/null 2> "$TMP/bunny.err"
check "open mesh: a warning, and spheres" grep -q "not closed" "$TMP/bunny.err"

# compare: scores our own output; a perfect-ish fit has small dice
"$MSS" compare "$DATA/ellipsoid_2_1_1.stl" "$TMP/e.txt" --resolution 50 > "$TMP/cmp.log"
dice=$(awk '/^dice/{print $2}' "$TMP/cmp.log")
check "compare dice < 0.1 for 6 spheres ($dice)" awk -v d="$dice" 'BEGIN{exit !(d > 0 && d < 0.1)}'
# a deliberately bad sphere set scores badly
printf 'x,y,z,r\n5,5,5,0.5\n' > "$TMP/bad.csv"
expect_error "a sphere wholly outside the grain's box: another frame?" "another frame" "$MSS" compare "$DATA/ellipsoid_2_1_1.stl" "$TMP/bad.csv"
"$MSS" compare "$DATA/ellipsoid_2_1_1.stl" "$TMP/bad.csv" --resolution 30 --align none > "$TMP/cmp2.log"
check "--align none scores it as written: outside = 1" grep -qE '^outside +1$' "$TMP/cmp2.log"

# comparisons with real CLUMP outputs (tests/data/clump): every format they write, frames, one table
C="$DATA/clump"
"$MSS" compare "$DATA/human_femur.stl" "$C/FA_femur_N70_min.vtk" > "$TMP/fa.log"
d=$(awk '/^dice/{print $2}' "$TMP/fa.log")
check "CLUMP Favier VTK of the femur reads and scores D 0.604 +- 0.02 ($d)" awk -v d="$d" 'BEGIN{exit !(d > 0.584 && d < 0.624)}'
check "compare reports the largest protrusion" grep -qE '^protrusion +[0-9.]+' "$TMP/fa.log"
expect_error "CLUMP Euclidean femur as written: another frame, --align suggested" "register it with --align (bbox, centroid or principal)" \
  "$MSS" compare "$DATA/human_femur.stl" "$C/EU_femur_N70_div150_rMin4_ov0.95.txt"
d=$("$MSS" compare "$DATA/human_femur.stl" "$C/EU_femur_N70_div150_rMin4_ov0.95.txt" --align bbox | awk '/^dice/{print $2}')
check "--align bbox: D <= 0.085 ($d)" awk -v d="$d" 'BEGIN{exit !(d > 0 && d <= 0.085)}'
printf ' -1.800000, -0.000000, -0.000000,  0.200000\r\n' > "$TMP/matlab.txt"
tail -n +2 "$C/FA_ellipsoid_N10_min.txt" | awk -F, '{printf "%10f,%10f,%10f,%10f\r\n", $1, $2, $3, $4}' >> "$TMP/matlab.txt"
"$MSS" compare "$DATA/ellipsoid_2_1_1.stl" "$C/FA_ellipsoid_N10_min.txt" "$TMP/matlab.txt" "$C/FA_ellipsoid_N10_min.vtk" --csv "$TMP/table.csv" > "$TMP/table.log"
check "one table, one row per file (3 rows + header)" [ "$(wc -l < "$TMP/table.csv")" -eq 4 ]
check "CLUMP's MATLAB form reads as its Python form (same D)" \
  bash -c "[ \"\$(sed -n 2p $TMP/table.csv | cut -d, -f3)\" = \"\$(sed -n 3p $TMP/table.csv | cut -d, -f3)\" ]"
# one file in another frame is a row with its error (naming it), the others are scored; the status says it
"$MSS" compare "$DATA/human_femur.stl" "$C/EU_femur_N70_div150_rMin4_ov0.95.txt" "$C/FA_femur_N70_min.txt" \
  --resolution 40 --csv "$TMP/mixed.csv" > "$TMP/mixed.log" 2> "$TMP/mixed.err"
rc=$?
check "a table with one file in another frame: status 1 ($rc)" [ "$rc" -eq 1 ]
check "its row names the file at fault" grep -q "error: $C/EU_femur_N70_div150_rMin4_ov0.95.txt: compare:" "$TMP/mixed.log"
check "the other file is scored" grep -qE 'FA_femur_N70_min.txt +70 +0\.[0-9]+' "$TMP/mixed.log"
check "the CSV has both rows, the error in its column" grep -q 'another frame' "$TMP/mixed.csv"
# --align registers only what lies in another frame: our own file keeps its D
"$MSS" generate "$DATA/human_femur.stl" --spheres 20 --resolution 40 -o "$TMP/ours20.csv" > /dev/null
d1=$("$MSS" compare "$DATA/human_femur.stl" "$TMP/ours20.csv" --resolution 40 | awk '/^dice/{print $2}')
d2=$("$MSS" compare "$DATA/human_femur.stl" "$TMP/ours20.csv" --resolution 40 --align principal | awk '/^dice/{print $2}')
check "--align principal leaves a file in the grain's frame as it is ($d1 = $d2)" [ "$d1" = "$d2" ]
expect_error "bad --align" "--align must be one of centroid, bbox, principal, none" "$MSS" compare "$DATA/ellipsoid_2_1_1.stl" "$C/FA_ellipsoid_N10_min.txt" --align box

# batch: a labelled volume to an assembly, through the mss command
"$MSS" batch "$DATA/two_grains_labels.npy" -o "$TMP/batch" --spheres 5 --voxel-size 0.001 --workers 1 > "$TMP/batch.log"
check "batch: both grains ok in grains.csv" [ "$(grep -c ',ok,' "$TMP/batch/grains.csv")" -eq 2 ]
check "batch: assembly with two clumps" [ "$(grep -c '^#mss clump' "$TMP/batch/assembly.txt")" -eq 2 ]
expect_error "batch without -o" "required" "$MSS" batch "$DATA/two_grains_labels.npy" --spheres 5

# the Python commands name a bad --origin
expect_error "batch: bad origin" "--origin: .1,2. is not X,Y,Z" "$MSS" batch "$DATA/two_grains_labels.npy" -o "$TMP/bo" --spheres 3 --origin 1,2
expect_error "preview: bad origin" "--origin: .1,x,2. is not X,Y,Z" "$MSS" preview "$DATA/ellipsoid_2_1_1.stl" "$TMP/e.csv" -o "$TMP/o.png" --origin 1,x,2

# info
"$MSS" info "$DATA/human_femur.stl" > "$TMP/info.log"
check "info reports 13752 triangles" grep -qE '^triangles +13752' "$TMP/info.log"
check "info reports closed" grep -qE '^closed +yes' "$TMP/info.log"

# errors: clear message, non-zero exit, no output file left behind
expect_error "missing input" "cannot open" "$MSS" generate "$TMP/nope.stl" --spheres 3 -o "$TMP/x.csv"
expect_error "unknown extension" "unknown mesh extension" "$MSS" info "$TMP/x.abc"
: > "$TMP/empty.stl"
expect_error "empty file" "empty" "$MSS" info "$TMP/empty.stl"
expect_error "zero spheres" "--spheres must be in .1, 65535., got 0" "$MSS" generate "$DATA/ellipsoid_2_1_1.stl" --spheres 0 -o "$TMP/x.csv"
expect_error "no criterion" "termination criterion" "$MSS" generate "$DATA/ellipsoid_2_1_1.stl" -o "$TMP/x.csv"
expect_error "resolution 0" "resolution must be >= 1" "$MSS" generate "$DATA/ellipsoid_2_1_1.stl" --spheres 3 --resolution 0 -o "$TMP/x.csv"
expect_error "absurd resolution" "would need" "$MSS" generate "$DATA/ellipsoid_2_1_1.stl" --spheres 3 --resolution 200000 -o "$TMP/x.csv"
expect_error "bad output extension" "unknown output extension" "$MSS" generate "$DATA/ellipsoid_2_1_1.stl" --spheres 3 -o "$TMP/x.doc"
expect_error "unwritable output" "cannot write" "$MSS" generate "$DATA/ellipsoid_2_1_1.stl" --spheres 3 --resolution 20 -o /nonexistent-dir/x.csv
expect_error "unknown option names the closest" "unknown option '--sphere': did you mean '--spheres'?" "$MSS" generate "$DATA/ellipsoid_2_1_1.stl" --sphere 3 -o "$TMP/x.csv"
expect_error "unknown compare option" "did you mean '--offset'" "$MSS" compare "$DATA/ellipsoid_2_1_1.stl" "$TMP/e.csv" --ofset 0.3
expect_error "unknown command" "unknown command 'generat'" "$MSS" generat "$DATA/ellipsoid_2_1_1.stl"
expect_error "missing output" "generate needs -o OUT" "$MSS" generate "$DATA/ellipsoid_2_1_1.stl" --spheres 3
"$MSS" generate --help > "$TMP/help.log"
check "generate --help lists its options, exit 0" grep -q -- "--clip" "$TMP/help.log"
check "compare --help lists --clump, not generate's --spheres" bash -c "\"$MSS\" compare --help | grep -q -- --clump && ! \"$MSS\" compare --help | grep -q -- --spheres"
expect_error "bad number" "not an integer" "$MSS" generate "$DATA/ellipsoid_2_1_1.stl" --spheres abc -o "$TMP/x.csv"
check "no file left by failed runs" [ ! -e "$TMP/x.csv" ]

# safe writes (the bugs: compare --csv wrote a fixed OUT.tmp and followed a symlink planted there; generate -o used
# OUT.tmp<PID>; --csv renamed over a device node)
echo "precious" > "$TMP/victim"
ln -s "$TMP/victim" "$TMP/table.csv.tmp"
for pid in $(seq $$ $(($$ + 40))); do ln -sf "$TMP/victim" "$TMP/sp.csv.tmp$pid"; done
"$MSS" compare "$DATA/ellipsoid_2_1_1.stl" "$TMP/e.csv" --csv "$TMP/table.csv" > /dev/null
"$MSS" generate "$DATA/ellipsoid_2_1_1.stl" --spheres 3 --resolution 20 -o "$TMP/sp.csv" > /dev/null
check "planted symlinks are not followed" [ "$(cat "$TMP/victim")" = "precious" ]
check "the table was written" grep -q dice "$TMP/table.csv"
check "the spheres were written" [ "$(wc -l < "$TMP/sp.csv")" -eq 4 ]
ln -s "$TMP/victim" "$TMP/link.csv"
expect_error "a symlink as output is refused" "not a regular file" "$MSS" generate "$DATA/ellipsoid_2_1_1.stl" --spheres 3 --resolution 20 -o "$TMP/link.csv"
expect_error "a device as --csv is refused" "not a regular file" "$MSS" compare "$DATA/ellipsoid_2_1_1.stl" "$TMP/e.csv" --csv /dev/null
check "the victim is still the victim" [ "$(cat "$TMP/victim")" = "precious" ]
check "no temporary file left" [ -z "$(find "$TMP" -maxdepth 1 -name '.*.??????' -print -quit)" ]

# inputs that are not regular files are refused by name, at once (the bug: a FIFO hung generate, info, compare)
mkfifo "$TMP/pipe.stl"
expect_error "a FIFO as input" "not a regular file (a FIFO)" timeout 20 "$MSS" info "$TMP/pipe.stl"
expect_error "a FIFO to generate" "not a regular file (a FIFO)" timeout 20 "$MSS" generate "$TMP/pipe.stl" --spheres 3 -o "$TMP/x.csv"
expect_error "a huge thread count (the bug: a segfault)" "threads must be in .0, 1024., got 65536" "$MSS" generate "$DATA/ellipsoid_2_1_1.stl" --spheres 3 --resolution 20 --threads 65536 -o "$TMP/x.csv"
expect_error "2000 threads (the bug: libgomp's Thread creation failed)" "threads must be in .0, 1024., got 2000" "$MSS" generate "$DATA/ellipsoid_2_1_1.stl" --spheres 3 --resolution 20 --threads 2000 -o "$TMP/x.csv"
for lim in nan -1 1e12 inf; do
  expect_error "--memory-limit $lim (the bug: the guard off, or 'a limit of 0 GiB')" "memory-limit must be in" "$MSS" generate "$DATA/ellipsoid_2_1_1.stl" --spheres 3 --resolution 20 --memory-limit "$lim" -o "$TMP/x.csv"
done
expect_error "compare --offset 1e300 (the bug: D 0, a perfect score)" "offset must be in .0, 1. voxel, got 1e+300" "$MSS" compare "$DATA/ellipsoid_2_1_1.stl" "$TMP/e.csv" --offset 1e300
expect_error "curve --points 0" "points must be in" "$MSS" curve "$DATA/ellipsoid_2_1_1.stl" --counts 2:4 --points 0 -o "$TMP/c.png"
printf 'solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n' > "$TMP/flat.stl"
expect_error "a flat solid names its file (generate)" "flat.stl: voxelizeMesh: the solid is flat" "$MSS" generate "$TMP/flat.stl" --spheres 3 -o "$TMP/x.csv"
expect_error "a flat solid names its file (compare)" "flat.stl: " "$MSS" compare "$TMP/flat.stl" "$TMP/e.csv"
expect_error "--label on a mesh (the bug: ignored)" "--label applies to voxel volumes" "$MSS" generate "$DATA/cube.stl" --spheres 3 --label 2 -o "$TMP/x.csv"
mkfifo "$TMP/pipe.npy" "$TMP/pipe.png"
expect_error "a FIFO to batch (the bug: a hang)" "not a regular file (a FIFO)" timeout 60 "$MSS" batch "$TMP/pipe.npy" -o "$TMP/bo" --spheres 3
expect_error "a FIFO to spheropolygon (the bug: a hang)" "not a regular file (a FIFO)" timeout 60 "$MSS" spheropolygon "$TMP/pipe.png" -o "$TMP/sp.json"
expect_error "over 2^31 voxels says so (the bug: '931 GiB, over the limit of 1.02e+03 GiB')" "more than a grid can index" "$MSS" generate "$DATA/cube.stl" --spheres 3 --resolution 1300 --memory-limit 100000 -o "$TMP/x.csv"
printf 'x,y,z,r\n1e300,0,0,1e200\n' > "$TMP/huge.csv"
expect_error "spheres too large to sample (the bug: 'only -nan%'), then a SIGFPE in surface" "outside the range this code computes in" "$MSS" compare "$DATA/cube.stl" "$TMP/huge.csv"
expect_error "a radius near the double range in surface (the bug: SIGFPE)" "outside the range this code computes in" "$MSS" surface "$TMP/huge.csv" -o "$TMP/huge.stl"
expect_error "/dev/zero as a sphere file" "not a regular file (a character device)" timeout 20 "$MSS" compare "$DATA/ellipsoid_2_1_1.stl" /dev/zero

# spheropolygon -o replaces only regular files: a device, or a link planted to one, is refused by name
/usr/bin/python3 -c "import numpy as np; a = np.zeros((40, 40), np.uint8); a[10:30, 8:32] = 1; np.save('$TMP/img.npy', a)"
expect_error "spheropolygon -o a device" "/dev/full: exists and is not a regular file" "$MSS" spheropolygon "$TMP/img.npy" -o /dev/full
ln -s /dev/full "$TMP/planted.json"
expect_error "spheropolygon -o a link to a device" "planted.json: exists and is not a regular file" "$MSS" spheropolygon "$TMP/img.npy" -o "$TMP/planted.json"
check "the planted link is left as it was" [ "$(readlink "$TMP/planted.json")" = /dev/full ]

# the installed mss runs the installed package (the bug: it put the build tree first on PYTHONPATH); the build
# tree's runs the build tree's. Installed here into a folder of the test's own.
mss_abs=$(realpath "$MSS")
if [ ! -f "$(dirname "$mss_abs")/py/yade_mss/__init__.py" ]; then
  echo "not run: the installed-package checks (this build, $(dirname "$mss_abs"), has no Python package)"
elif cmake --install "$(dirname "$MSS")" --prefix "$TMP/inst" > "$TMP/install.log" 2>&1; then
  site=$(echo "$TMP"/inst/lib/python3*/dist-packages)
  from=$(cd "$TMP" && PYTHONVERBOSE=1 PYTHONPATH="$site" "$TMP/inst/bin/mss" spheropolygon "$TMP/img.npy" -o "$TMP/i.json" 2>&1 | grep -m1 'code object from .*yade_mss/__init__.py')
  check "installed mss imports yade_mss from $site (got: $from)" grep -qF "$site/yade_mss/__init__.py" <<<"$from"
  from=$(cd "$TMP" && PYTHONVERBOSE=1 PYTHONPATH="$site" "$mss_abs" spheropolygon "$TMP/img.npy" -o "$TMP/b.json" 2>&1 | grep -m1 'code object from .*yade_mss/__init__.py')
  check "the build tree's mss imports its own yade_mss (got: $from)" grep -qF "$(dirname "$mss_abs")/py/yade_mss/__init__.py" <<<"$from"
else
  fail=$((fail + 1)); echo "FAILED: cmake --install into $TMP/inst: $(tail -3 "$TMP/install.log")"
fi

# a file cut short while it is read gives an error or a result, never SIGBUS (the bug: mapped files died so);
# a 50 MB binary STL truncated to 1000 bytes at delays that fall in the read
/usr/bin/python3 -c "
import struct, numpy as np
t = np.zeros(1000000, dtype=[('n', '<f4', 3), ('v', '<f4', (3, 3)), ('a', '<u2')])
t['v'] = np.random.default_rng(1).random((len(t), 3, 3))
with open('$TMP/big.stl', 'wb') as f:
    f.write(b'x' * 80 + struct.pack('<I', len(t)) + t.tobytes())"
signalled=0
for delay in 0 0.01 0.02 0.04 0.06 0.08 0.1 0.15 0.2 0.3; do
  cp "$TMP/big.stl" "$TMP/shrinking.stl"
  "$MSS" info "$TMP/shrinking.stl" > /dev/null 2>&1 &
  pid=$!
  sleep "$delay"
  truncate -s 1000 "$TMP/shrinking.stl"
  wait "$pid"
  rc=$?
  [ "$rc" -ge 128 ] && signalled=$((signalled + 1)) && echo "  delay $delay: exit $rc"
done
check "a file truncated while read never kills mss by a signal ($signalled of 10 did)" [ "$signalled" -eq 0 ]
rm -f "$TMP/big.stl" "$TMP/shrinking.stl"

# a memory limit above what the machine gives: a message, not a bare std::bad_alloc (the bug); the address
# space is capped at 6 GB here so that the machine's own memory is never touched
# (not under AddressSanitizer: its shadow memory needs the address space that the cap takes away, and the
# grids are mapped past its allocator; the release build runs it)
if grep -qa __asan_init "$MSS"; then
  echo "not run: out of memory under a capped address space (an AddressSanitizer build)"
else
  expect_error "out of memory names the remedy (the bug: 'std::bad_alloc')" "out of memory: the machine could not give" \
    bash -c "ulimit -v 6000000; exec \"\$0\" generate \"\$1\" --spheres 3 --resolution 1200 --memory-limit 100000 -o \"\$2\"" "$MSS" "$DATA/cube.stl" "$TMP/x.csv"
fi

# no output over an input (issue 50): refused before any work, with both names, the input unchanged; through a
# link too
"$MSS" generate "$DATA/ellipsoid_2_1_1.stl" --spheres 4 --resolution 30 -o "$TMP/ovr_in.csv" > /dev/null
cp "$TMP/ovr_in.csv" "$TMP/ovr_in.keep"
expect_error "compare --csv over its sphere file" "is the input" "$MSS" compare "$DATA/ellipsoid_2_1_1.stl" "$TMP/ovr_in.csv" --csv "$TMP/ovr_in.csv"
ln -s "$TMP/ovr_in.csv" "$TMP/ovr_link.csv"
expect_error "compare --csv over its sphere file through a link" "through a link" "$MSS" compare "$DATA/ellipsoid_2_1_1.stl" "$TMP/ovr_in.csv" --csv "$TMP/ovr_link.csv"
expect_error "surface -o over its sphere file" "is the input" "$MSS" surface "$TMP/ovr_in.csv" -o "$TMP/ovr_link.csv"
cp "$DATA/cube.stl" "$TMP/ovr_cube.stl"
expect_error "generate -o over its mesh" "is the input" "$MSS" generate "$TMP/ovr_cube.stl" --spheres 2 -o "$TMP/ovr_cube.stl"
expect_error "export -o over its mesh" "is the input" "$MSS" export "$TMP/ovr_cube.stl" --spheres 2 --format pfc -o "$TMP/ovr_cube.stl"
check "the inputs are unchanged" cmp -s "$TMP/ovr_in.csv" "$TMP/ovr_in.keep"
check "the mesh is unchanged" cmp -s "$TMP/ovr_cube.stl" "$DATA/cube.stl"
expect_error "generate -o and --preview the same file" "name the same file" "$MSS" generate "$DATA/cube.stl" --spheres 2 -o "$TMP/same.csv" --preview "$TMP/same.csv"
expect_error "curve's CSV over its --compare input" "is the input" "$MSS" curve "$DATA/cube.stl" --counts 2:4 --points 2 -o "$TMP/ovr_in.png" --compare "$TMP/ovr_in.csv"
expect_error "ochart --dice without --min-cost" "applies with --min-cost" "$MSS" ochart "$DATA/cube.stl" --dice 0.05 -o "$TMP/o.png"
# a command that fails publishes nothing: the spheres only once their preview is drawn
rm -f "$TMP/failed.csv"
expect_error "generate with a preview it cannot write" "preview" "$MSS" generate "$DATA/cube.stl" --spheres 2 --resolution 20 -o "$TMP/failed.csv" --preview "$TMP/no/such/folder/p.png"
check "no sphere file left by the failed command" [ ! -e "$TMP/failed.csv" ]
check "no temporary file left beside it" [ -z "$(ls -A "$TMP" | grep mss-pending)" ]
"$MSS" generate "$DATA/cube.stl" --spheres 2 --resolution 20 -o "$TMP/ok.csv" --preview "$TMP/ok.png" > /dev/null
check "with its preview drawn, the spheres are written" [ -s "$TMP/ok.csv" ] && [ -s "$TMP/ok.png" ]
# the help's range is the check's (the bug: --help said [1, 16], the voxeliser refused 9..16)
check "--help gives --supersample's real range" bash -c '"$0" generate --help | grep -- --supersample | grep -qF "[1, 8]"' "$MSS"
expect_error "--supersample 9 refused by the option's range" "supersample" "$MSS" generate "$DATA/cube.stl" --spheres 2 --supersample 9 -o "$TMP/s9.csv"
# sphere files are read by their header's names
printf 'r,x,y,z\n0.5,1,2,3\n' > "$TMP/named.csv"
"$MSS" surface "$TMP/named.csv" -o "$TMP/named.stl" > "$TMP/named.log"
check "columns by the header's names (r first)" grep -qE '^union_volume +0.523' "$TMP/named.log"
printf 'x,y,radius,q\n1,2,0.5,3\n' > "$TMP/lacks.csv"
expect_error "a header without z is refused by name" "names no column z" "$MSS" surface "$TMP/lacks.csv" -o "$TMP/l.stl"

echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
