#!/usr/bin/env bash
# `fuzzycsg convert` with its defaults on the OpenSCAD models rendered to meshes (their .ref.off),
# the CAD meshes of the data collection, the OpenSCAD models themselves (.csg) and nine glyphs
# (pictures), one row per shape: primitives (and the original
# program's count, where known), IoU, Chamfer and Hausdorff distances to the mesh, and time.
# Usage: scripts/convert-study.sh [FUZZYCSG [OUTDIR [THREADS]]]
# Writes OUTDIR/<shape>/ (every output of convert), OUTDIR/shapes.txt (the meshes' rows below),
# OUTDIR/table.md (the meshes), OUTDIR/models.md (the OpenSCAD models given as .csg) and
# OUTDIR/pictures.md (glyphs). STUDY_SETS="meshes models pictures" (the default) chooses which
# to convert and tabulate.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/data-dir.sh
bin=${1:-build/release/apps/fuzzycsg/fuzzycsg}
out=${2:-/tmp/fuzzycsg-convert-study}
threads=${3:-2}
scad=$(fuzzycsg_data_dir scad) || exit 2
cad=$(fuzzycsg_data_dir meshes/cad) || exit 2
mkdir -p "$out"

# shape, mesh, primitives of the original program ("-" where there is none), tuned on or held out
shapes=(
  "CSG $scad/Basics/CSG.ref.off 6 tuned"
  "logo $scad/Basics/logo.ref.off 4 held-out"
  "example001 $scad/Old/example001.ref.off 4 tuned"
  "example003 $scad/Old/example003.ref.off 7 held-out"
  "example004 $scad/Old/example004.ref.off 2 held-out"
  "hole $cad/cgal_hole.off - tuned"
  "u $cad/cgal_u.off - tuned"
  "pipe $cad/cgal_pipe.off - held-out"
  "cross $cad/cgal_cross.off - held-out"
  "corner $cad/cgal_corner.off - held-out"
  "P $cad/cgal_P.off - tuned"
  "couplingdown $cad/cgal_couplingdown.off - held-out"
  "fandisk $cad/cgal_fandisk.off - held-out"
  "pinion $cad/cgal_pinion.off - held-out"
)
# The same OpenSCAD models given as the programs themselves (`openscad -o x.csg`, .openscad.csg):
# the target is the model's exact solid, not its faceted mesh.
models=(
  "CSG.csg $scad/Basics/CSG.openscad.csg 6 tuned"
  "logo.csg $scad/Basics/logo.openscad.csg 4 held-out"
  "example001.csg $scad/Old/example001.openscad.csg 4 held-out"
  "example003.csg $scad/Old/example003.openscad.csg 7 held-out"
  "example004.csg $scad/Old/example004.openscad.csg 2 tuned"
)
# Pictures: the nine glyphs of the 2D study of Fig. 12 (docs/results.md).
glyphs=$(fuzzycsg_data_dir glyphs) || exit 2
pictures=()
for g in 0026_ampersand 002B_plus 0030_0 0038_8 003F_question 0045_E 0050_P 0062_b 0069_i; do
  tuned=held-out
  [[ $g == 0050_P ]] && tuned=tuned
  pictures+=("glyph-${g#*_} $glyphs/DejaVuSans-Bold_U$g.png - $tuned")
done
printf '%s\n' "${shapes[@]}" >"$out/shapes.txt"  # read by bench/convert_vs_fit.py
# STUDY_SETS: which of the three to convert (the tables are written for all that have results).
sets=${STUDY_SETS:-meshes models pictures}
rows=()
[[ $sets == *meshes* ]] && rows+=("${shapes[@]}")
[[ $sets == *models* ]] && rows+=("${models[@]}")
[[ $sets == *pictures* ]] && rows+=("${pictures[@]}")
for row in "${rows[@]}"; do
  read -r name input _ _ <<<"$row"
  [[ -n "${ONLY_TABLE:-}" ]] && continue
  "$bin" convert "$input" -o "$out/$name" --threads "$threads" -q 2>"$out/$name.err" ||
    echo "convert: $name failed: $(tail -1 "$out/$name.err")" >&2
done
table() {
  python3 -c '
import json, os, sys
out = sys.argv[1]
print("| shape | tuned on | primitives (original) | IoU | Chamfer | Hausdorff | seconds |")
print("|---|---|---|---|---|---|---|")
for line in sys.stdin:
    name, mesh, known, tuned = line.split()
    path = os.path.join(out, name, "report.json")
    if not os.path.exists(path):
        print(f"| {name} | {tuned} | failed | | | | |")
        continue
    r = json.load(open(path))
    m = r["metrics"]
    f = lambda v: "-" if v is None else "%.3g" % v
    row = (name, tuned, r["primitives"], known, m["iou"], f(m["chamfer"]), f(m["hausdorff"]),
           r["seconds"]["total"])
    print("| %s | %s | %d (%s) | %.4f | %s | %s | %.1f |" % row)
' "$out"
}
[[ $sets == *meshes* ]] && printf '%s\n' "${shapes[@]}" | table | tee "$out/table.md"
[[ $sets == *models* ]] && printf '%s\n' "${models[@]}" | table | tee "$out/models.md"
[[ $sets == *pictures* ]] && printf '%s\n' "${pictures[@]}" | table | tee "$out/pictures.md"
exit 0
