#!/bin/bash
# Whether two builds of `mss` write the same bytes: every shared mesh, the CT grain and both grains of the
# labelled volume, generated (.csv, .txt, .vtk) in several modes and compared (the text the command prints
# minus its timings). A change meant to leave behaviour alone passes this.
#   scripts/same_outputs.sh OLD_MSS NEW_MSS [DATA]
set -u
OLD=$1 NEW=$2 DATA=${3:-tests/data}
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
same=0 differ=0
run() { # name, args...
  local name=$1
  shift
  for side in old new; do
    local bin=$OLD
    [ $side = new ] && bin=$NEW
    mkdir -p "$TMP/$side"
    "$bin" "$@" -o "$TMP/$side/$name.${EXT:-csv}" 2>&1 | grep -v '^seconds\|^wrote' > "$TMP/$side/$name.log"
    "$bin" compare "${@:2:1}" "$TMP/$side/$name.${EXT:-csv}" ${CMP_ARGS:-} 2>&1 > "$TMP/$side/$name.cmp"
  done
  if cmp -s "$TMP/old/$name.${EXT:-csv}" "$TMP/new/$name.${EXT:-csv}" && cmp -s "$TMP/old/$name.log" "$TMP/new/$name.log" &&
    cmp -s "$TMP/old/$name.cmp" "$TMP/new/$name.cmp"; then
    same=$((same + 1))
  else
    differ=$((differ + 1))
    echo "DIFFER: $name ($*)"
  fi
}
for m in cube ellipsoid_2_1_1 human_femur octahedron sphere_r1 stanford_bunny_open torus; do
  run "$m-10" generate "$DATA/$m.stl" --spheres 10 --resolution 60
  run "$m-dice" generate "$DATA/$m.stl" --dice 0.05 --resolution 50 --clip
  run "$m-paper" generate "$DATA/$m.stl" --spheres 8 --resolution 40 --method paper
done
EXT=txt run femur-txt generate "$DATA/human_femur.stl" --spheres 20 --voxel-size 0.8 --max-protrusion inf
EXT=vtk run ellipsoid-vtk generate "$DATA/ellipsoid_2_1_1.stl" --spheres 5 --resolution 30 --no-symmetry --no-refill --max-protrusion 0.05
CMP_ARGS="--plane 0,0,0,0,0,1 --resolution 80" run plane generate "$DATA/cube.stl" --spheres 6 --resolution 40 --plane 0,0,0,0,0,1
run ct-grain generate "$DATA/grain_voxels_155x157x167.npy" --spheres 30
run ct-grain-clip generate "$DATA/grain_voxels_155x157x167.npy" --dice 0.08 --clip
for l in 1 2; do CMP_ARGS="--label $l" run "labels-$l" generate "$DATA/two_grains_labels.npy" --label $l --spheres 10; done
echo "same_outputs: $same same, $differ differ"
[ $differ -eq 0 ]
