#!/usr/bin/env bash
# The convert verb driven as a user would: a crisp program of CAD primitives with every output,
# the same tree for the same seed, a word when the IoU asked for is not reached, and one-line
# errors with nothing written for bad input. Usage: convert_cli_test.sh PATH/TO/fuzzycsg SOURCE_DIR
#
# Under the sanitizers (FUZZYCSG_SANITIZED=1) the search runs once, on the hole, with the checks
# that one run allows: the bracket and the second, same-seed run take minutes there and add
# little that the one run does not exercise, so they run in the release suite only.
set -u
bin=$1
src=$2
source "$(dirname "$0")/lib.sh"
sanitized=${FUZZYCSG_SANITIZED:-0}
hole="$src/tests/data/meshes/cad/cgal_hole.off"

# The demo's bracket (6 primitives) comes back as a crisp program of at most 8 CAD primitives at
# IoU >= 0.98, with every output; OpenSCAD primitives only. Not under the sanitizers.
if [[ $sanitized == 1 ]]; then
  :
elif "$bin" demo -o "$tmp/cdemo" --threads 2 >"$tmp/cdemo.log" 2>&1 &&
    python3 - "$tmp/cdemo" <<'PY'
import json, sys
d = sys.argv[1]
r = json.load(open(d + "/report.json"))
assert r["metrics"]["iou"] >= 0.98 and 1 <= r["primitives"] <= 8, r["metrics"]
assert r["metrics"]["chamfer"] is not None and r["metrics"]["hausdorff"] is not None
t = json.load(open(d + "/tree.json"))
def walk(n):
    if "children" in n:
        assert n["op"] in ("union", "intersection", "difference"), n
        for c in n["children"]: walk(c)
    else:
        assert n["type"] in ("box", "cylinder", "cone", "sphere", "torus", "plane", "extrude"), n
        assert "sharpness" not in n, n
walk(t["root"])
scad = open(d + "/model.scad").read()
assert "polyhedron" not in scad and "written by fuzzycsg convert" in scad
for f in ("render.png", "part.obj", "part.json"):
    assert open(d + "/" + f, "rb").read(4), f
PY
then ok; else bad "demo (convert): $(tail -5 "$tmp/cdemo.log")"; fi
# The hole, asking for an IoU it cannot reach (--warn-iou 1, which changes no tree): it says so on
# stderr and in report.json, and writes its tree all the same.
if "$bin" convert "$hole" -o "$tmp/cv2" --seed 3 --threads 2 -q --warn-iou 1 2>"$tmp/cv2.err" &&
    python3 - "$tmp/cv2" "$tmp/cv2.err" <<'PY'
import json, sys
r = json.load(open(sys.argv[1] + "/report.json"))
assert r["metrics"]["iou"] >= 0.95 and r["primitives"] <= 4, r
assert r["time_limit_reached"] is False, r
assert r["reached"] is False and r["settings"]["warn_iou"] == 1, r
err = open(sys.argv[2]).read().splitlines()
assert len(err) == 1 and "is below 1; the best tree found is written" in err[0], err
PY
then ok; else bad "convert: a poor result, or no word of the IoU not reached"; fi
# The output folder is replaced as a set. A run killed before it ends leaves the earlier set as
# it was; the next run puts its own in its place whole, and no temporary folder stays beside it.
cp -r "$tmp/cv2" "$tmp/cv2.before"
"$bin" convert "$hole" -o "$tmp/cv2" --seed 4 --threads 2 -q --no-tidy &
pid=$!
sleep 1
kill -9 "$pid"
wait "$pid" 2>/dev/null
if diff -r "$tmp/cv2" "$tmp/cv2.before" >/dev/null; then ok; else bad "convert: a killed run changed the earlier outputs"; fi
if "$bin" convert "$hole" -o "$tmp/cv2" --seed 4 --threads 2 -q --max-primitives 1 --warn-iou 0 &&
    ! cmp -s "$tmp/cv2/tree.json" "$tmp/cv2.before/tree.json" &&
    [[ $(ls -A "$tmp/cv2" | sort | tr '\n' ' ') == "$(ls -A "$tmp/cv2.before" | sort | tr '\n' ' ')" ]] &&
    [[ -z $(find "$tmp" -maxdepth 1 -name '.cv2.fuzzycsg-*') ]] &&
    python3 -c 'import json,sys; assert json.load(open(sys.argv[1]))["primitives"] == 1' "$tmp/cv2/report.json"
then ok; else bad "convert: the outputs were not replaced as a set"; fi
rm -rf "$tmp/cv2"
mv "$tmp/cv2.before" "$tmp/cv2"
# The folder is checked before any work: a file in its place, or files of the user's in it, are
# refused in one line and left alone.
printf 'x' >"$tmp/a-file"
expect_error "a-file: cannot be the output folder" "$bin" convert "$hole" -o "$tmp/a-file"
mkdir -p "$tmp/mine"
echo keep >"$tmp/mine/notes.txt"
expect_error "mine: holds notes.txt, which this verb does not write" "$bin" convert "$hole" -o "$tmp/mine"
if [[ $(cat "$tmp/mine/notes.txt") == keep && $(ls -A "$tmp/mine") == notes.txt ]]; then ok
else bad "convert: a refused output folder was changed"; fi
# The same seed and thread count give the same tree, which sits where the mesh does; without
# --warn-iou, "reached" compares with the default bar (0.97). Not under the sanitizers.
if [[ $sanitized == 1 ]]; then
  :
elif "$bin" convert "$hole" -o "$tmp/cv1" --seed 3 --threads 2 -q &&
    cmp -s "$tmp/cv1/tree.json" "$tmp/cv2/tree.json" && cmp -s "$tmp/cv1/model.scad" "$tmp/cv2/model.scad" &&
    python3 - "$tmp/cv1" <<'PY'
import json, sys
r = json.load(open(sys.argv[1] + "/report.json"))
assert r["reached"] is (r["metrics"]["iou"] >= 0.97), r
PY
then ok; else bad "convert: not deterministic, or reached misreported"; fi
# An OpenSCAD model (.csg): a 30 mm cube less a ball of radius 20 comes back as those two
# primitives, measured against the model itself. Not under the sanitizers.
if [[ $sanitized == 1 ]]; then
  :
elif "$bin" convert "$src/tests/data/scad/Old/example004.openscad.csg" -o "$tmp/cvcsg" --threads 2 -q &&
    python3 - "$tmp/cvcsg" <<'PY'
import json, sys
d = sys.argv[1]
r = json.load(open(d + "/report.json"))
assert r["metrics"]["iou"] >= 0.99 and r["primitives"] == 2, r["metrics"]
assert r["target"].startswith("tree"), r["target"]
scad = open(d + "/model.scad").read()
assert "sphere(r = 20);" in scad and "cube([30, 30, 30], center = true);" in scad, scad
assert "against the model" in scad, scad
assert open(d + "/render.png", "rb").read(4) == b"\x89PNG"
PY
then ok; else bad "convert: an OpenSCAD model is not its own two primitives"; fi
# A picture: a crisp 2D program of circles and squares, drawn over the picture.
# (run from its parent, with a relative output folder)
if (cd "$tmp" && "$bin" convert "$src/tests/data/glyphs/DejaVuSans-Bold_U0050_P.png" -o cvpic --threads 2 -q) &&
    python3 - "$tmp/cvpic" <<'PY'
import json, sys
d = sys.argv[1]
r = json.load(open(d + "/report.json"))
assert r["metrics"]["iou"] >= 0.97 and 2 <= r["primitives"] <= 8, r["metrics"]
assert set(r["primitive_kinds"]) <= {"circle", "rectangle"}, r["primitive_kinds"]
scad = open(d + "/model.scad").read()
assert "square(" in scad and "against the picture" in scad and "polygon" not in scad, scad
assert open(d + "/render.png", "rb").read(4) == b"\x89PNG"
PY
then ok; else bad "convert: a picture is not a crisp 2D program"; fi
# Bad input: one line, exit 2, nothing written.
cat >"$tmp/sphere.json" <<'JSON'
{"format": "fuzzycsg-tree", "version": 1, "dim": 3,
 "root": {"type": "sphere", "radius": 0.5}}
JSON
expect_error "no-such.off: no such file" "$bin" convert "$tmp/no-such.off" -o "$tmp/cvbad"
mkdir -p "$tmp/a-folder.off"
expect_error "a-folder.off: is a folder, not a mesh file" "$bin" convert "$tmp/a-folder.off" -o "$tmp/cvbad"
printf 'OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n' >"$tmp/open.off"
expect_error "open.off: mesh is open: 3 boundary edges" "$bin" convert "$tmp/open.off" -o "$tmp/cvbad"
printf 'OFF\n0 0 0\n' >"$tmp/nothing.off"
expect_error "nothing.off" "$bin" convert "$tmp/nothing.off" -o "$tmp/cvbad"
expect_error "sphere.json: convert takes a 3D mesh" "$bin" convert "$tmp/sphere.json" -o "$tmp/cvbad"
expect_error "--resolution" "$bin" convert "$hole" -o "$tmp/cvbad" --resolution 3
printf 'group() {\n  cube(size = [1, 1, 1]\n}\n' >"$tmp/broken.csg"
expect_error "broken.csg: line 3: cube" "$bin" convert "$tmp/broken.csg" -o "$tmp/cvbad"
[[ -e "$tmp/cvbad" ]] && bad "convert: a refused input left an output directory" || ok

echo "$pass passed, $fail failed"
[[ $fail -eq 0 ]]
