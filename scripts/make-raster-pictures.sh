#!/usr/bin/env bash
# Draws the OpenSCAD examples of the data collection's scad/ (scripts/data-dir.sh) and examples/box_with_hole.json with
# `fuzzycsg raster` (CSG of meshed primitives by rays) into docs/diffcsg/: each primitive in its
# colour and the normal map. Builds the release preset first.
#   scripts/make-raster-pictures.sh
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/data-dir.sh
scad=$(fuzzycsg_data_dir scad) || exit 2
cmake --preset release > /dev/null
cmake --build build/release -j "$(nproc)" --target fuzzycsg
fuzzycsg=build/release/apps/fuzzycsg/fuzzycsg
out=docs/diffcsg
mkdir -p "$out"
for m in Basics/CSG Basics/logo Old/example001 Old/example003 Old/example004; do
  name=$(basename "$m")
  "$fuzzycsg" raster "$scad/$m.openscad.csg" -o "$out/$name.png" --shaded \
    --size 320 --camera 30,30,0
  "$fuzzycsg" raster "$scad/$m.openscad.csg" -o "$out/${name}_normals.png" \
    --size 320 --camera 30,30,0
done
"$fuzzycsg" raster examples/box_with_hole.json -o "$out/box_with_hole.png" --shaded \
  --size 320 --camera 60,35,3.2
"$fuzzycsg" raster examples/box_with_hole.json -o "$out/box_with_hole_normals.png" \
  --size 320 --camera 60,35,3.2
