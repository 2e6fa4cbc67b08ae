#!/usr/bin/env bash
# The trace and morph verbs driven as a user would: outputs, the report's numbers, exit
# statuses, one-line errors naming the file, and nothing written for bad input.
# Usage: trace_cli_test.sh PATH/TO/fuzzycsg SOURCE_DIR
set -u
bin=$1
src=$2
glyphs="$src/tests/data/glyphs"
source "$(dirname "$0")/lib.sh"

# check_report FILE: score = excess + uncovered + k * primitives, and the effort's numbers
# agree with each other.
check_report() {
  python3 - "$1" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
s = r["statistics"]
problems = []
if abs(r["score"] - (r["excess"] + r["uncovered"] + r["k"] * r["primitives"])) > 1e-6:
    problems.append("score != excess + uncovered + k * primitives")
if r["mismatch"] != r["excess"] + r["uncovered"]:
    problems.append("mismatch")
if r["primitives"] < 1:
    problems.append("no primitives")
if r["k"] != r["settings"]["k"]:
    problems.append("k differs from the settings'")
if s["stopped_by"] not in ("max-trees", "patience", "time-limit", "empty"):
    problems.append("stopped_by " + str(s["stopped_by"]))
# An empty picture is answered without a search ("empty").
if s["trees_evaluated"] < 1 or (s["stopped_by"] != "empty" and
                                s["tree_evaluations"] < s["trees_evaluated"]):
    problems.append("trees evaluated / tree evaluations")
if not (0 <= s["best_found_at"] <= s["trees_evaluated"]):
    problems.append("best_found_at")
if s["iterations"] > r["settings"]["max_trees"]:
    problems.append("iterations > max_trees")
for name in ("REP", "ADD", "CUT", "MOD"):
    op = s["operators"][name]
    if op["improved"] > op["tried"] or not (0 <= op["rate"] <= 1):
        problems.append("operator " + name)
if sum(s["operators"][n]["tried"] for n in s["operators"]) > s["iterations"]:
    problems.append("more perturbations tried than iterations")
best = s["best_score"]
if not best or any(b[1] > a[1] + 1e-9 for a, b in zip(best, best[1:])):
    problems.append("best_score history is not decreasing")
elif abs(best[-1][1] - r.get("refine", {}).get("before", r)["score"]) > 1e-6:
    problems.append("last best score differs from the search's score")
for key in ("population", "max_trees", "patience", "refocus", "initial_size", "initial_sd",
            "added_size", "added_sd", "probabilities", "iterations", "seed", "threads", "batch",
            "time_limit"):
    if key not in r["settings"]:
        problems.append("settings lack " + key)
if problems:
    print("; ".join(problems))
    sys.exit(1)
PY
}

glyph="$glyphs/DejaVuSans-Bold_U002B_plus.png"
small=(--population 12 --max-trees 40 --patience 40 --refocus 10 --initial-size 3 --iterations 10
       --batch 4)
if [[ ! -f "$glyph" ]]; then
  bad "no glyph at $glyph (tests/data)"
else
  # trace: every output, the report consistent, the tree readable by the other verbs.
  if "$bin" trace "$glyph" -o "$tmp/t" "${small[@]}" --threads 2 --seed 3 --k 20 >"$tmp/t.log" 2>&1; then
    ok
    for f in tree.json result.png primitives.svg report.json; do
      if [[ -s "$tmp/t/$f" ]]; then ok; else bad "trace did not write $f"; fi
    done
    if out=$(check_report "$tmp/t/report.json"); then ok; else bad "trace report.json: $out"; fi
    if python3 -c 'import json,sys; r=json.load(open(sys.argv[1])); s=r["settings"]
assert s["seed"] == 3 and s["population"] == 12 and s["k"] == 20 and r["bitmap"]["width"] == 128
assert "trace" in r["command_line"]' "$tmp/t/report.json"; then ok; else bad "trace settings"; fi
    if "$bin" info "$tmp/t/tree.json" | grep -qE "dimension +2"; then ok; else bad "tree.json does not read back"; fi
    n=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["primitives"])' "$tmp/t/report.json")
    if [[ $(grep -c 'class="primitive ' "$tmp/t/primitives.svg") -eq $n ]]; then ok; else
      bad "primitives.svg: $(grep -c 'class="primitive ' "$tmp/t/primitives.svg") outlines, $n primitives"
    fi
    if python3 -c 'import struct,sys; b=open(sys.argv[1],"rb").read(24); assert b[1:4]==b"PNG"
assert struct.unpack(">I", b[16:20])[0] >= 256' "$tmp/t/result.png"; then ok; else bad "result.png not scaled up"; fi
    if grep -q "wrote $tmp/t/{tree.json, result.png, primitives.svg, report.json}" "$tmp/t.log"; then ok; else
      bad "trace summary: $(tail -2 "$tmp/t.log")"
    fi
  else
    bad "trace: $(tail -5 "$tmp/t.log")"
  fi

  # --refine: never worse; the search's tree kept beside the result.
  if "$bin" trace "$glyph" -o "$tmp/r" "${small[@]}" --threads 2 --refine --refine-iterations 40 -q \
      2>"$tmp/err" && [[ -s "$tmp/r/search_tree.json" && -s "$tmp/r/tree.json" ]]; then
    if python3 -c 'import json,sys; r=json.load(open(sys.argv[1])); f=r["refine"]
assert f["after"]["score"] <= f["before"]["score"] and f["iterations"] == 40
assert abs(r["score"] - f["after"]["score"]) < 1e-9 and r["settings"]["refine"]["iterations"] == 40' \
        "$tmp/r/report.json"; then ok; else bad "trace --refine report"; fi
    if out=$(check_report "$tmp/r/report.json"); then ok; else bad "trace --refine report.json: $out"; fi
  else
    bad "trace --refine: $(cat "$tmp/err")"
  fi
  expect_error "--refine-iterations: only with --refine" "$bin" trace "$glyph" -o "$tmp/bad15" \
    --refine-iterations 5
  [[ -e "$tmp/bad15" ]] && bad "--refine-iterations without --refine left a directory" || ok

  # The same seed gives the same tree whatever the number of threads.
  if "$bin" trace "$glyph" -o "$tmp/t1" "${small[@]}" --seed 3 --k 20 --threads 1 -q &&
      cmp -s "$tmp/t/tree.json" "$tmp/t1/tree.json"; then ok; else bad "trace differs with --threads 1"; fi

  # --runs: the best and each distinct result, every run in the report.
  if "$bin" trace "$glyph" -o "$tmp/v" "${small[@]}" --threads 2 --runs 3 -q 2>"$tmp/err"; then
    if python3 - "$tmp/v" <<'PY'
import json, os, sys
d = sys.argv[1]
r = json.load(open(os.path.join(d, "report.json")))
assert len(r["runs"]) == 3, "runs"
assert [x["seed"] for x in r["runs"]] == [1, 2, 3], "seeds"
assert 1 <= len(r["distinct"]) <= 3, "distinct"
for x in r["distinct"]:
    for f in ("tree.json", "result.png"):
        assert os.path.getsize(os.path.join(d, x["directory"], f)) > 0, x["directory"] + f
scores = [x["score"] for x in r["distinct"]]
assert scores == sorted(scores), "distinct not sorted"
assert abs(r["score"] - scores[0]) < 1e-9, "best"
PY
    then ok; else bad "trace --runs report"; fi
    # One run into the same directory: the distinct results of the earlier runs go.
    if "$bin" trace "$glyph" -o "$tmp/v" "${small[@]}" --threads 2 -q && [[ ! -e "$tmp/v/distinct" ]] &&
        ! grep -q '"distinct"' "$tmp/v/report.json"; then ok; else bad "trace: stale distinct/ results"; fi
  else
    bad "trace --runs: $(cat "$tmp/err")"
  fi
fi

# Small pictures made here (the standard library's zlib, no imaging package): 1x1, empty, full,
# colour, and two of different sizes.
python3 - "$tmp" <<'PY'
import struct, sys, zlib
d = sys.argv[1]
def png(path, w, h, pixel, colour=False):
    rows = b"".join(b"\0" + b"".join(bytes(pixel(x, y)) for x in range(w)) for y in range(h))
    chunk = lambda t, b: struct.pack(">I", len(b)) + t + b + struct.pack(">I", zlib.crc32(t + b))
    ihdr = struct.pack(">IIBBBBB", w, h, 8, 2 if colour else 0, 0, 0, 0)
    open(path, "wb").write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) +
                           chunk(b"IDAT", zlib.compress(rows)) + chunk(b"IEND", b""))
png(d + "/one.png", 1, 1, lambda x, y: [0])
png(d + "/white.png", 24, 16, lambda x, y: [255])
png(d + "/black.png", 24, 16, lambda x, y: [0])
# A dark red disc of radius 12 (about 450 pixels) on light yellow.
png(d + "/colour.png", 40, 30, lambda x, y: [120, 0, 30] if (x + 0.5 - 20) ** 2 + (y + 0.5 - 15) ** 2 < 144
    else [250, 240, 200], colour=True)
png(d + "/disc.png", 40, 30, lambda x, y: [0 if (x + 0.5 - 15) ** 2 + (y + 0.5 - 15) ** 2 < 100 else 255])
png(d + "/bar.png", 40, 30, lambda x, y: [0 if 15 <= x < 36 and 8 <= y < 23 else 255])
png(d + "/tall.png", 30, 40, lambda x, y: [255])
png(d + "/blank.png", 40, 30, lambda x, y: [255])
png(d + "/dark.png", 40, 30, lambda x, y: [0])
PY
head -c 60 "$tmp/disc.png" >"$tmp/corrupt.png"
# A PNG header claiming 10000 x 10000 pixels.
printf '\x89PNG\r\n\x1a\n\x00\x00\x00\x0dIHDR\x00\x00\x27\x10\x00\x00\x27\x10\x08\x00\x00\x00\x00\x9f\x25\x3d\xfb' \
  >"$tmp/huge.png"
tiny=(--population 6 --max-trees 12 --patience 12 --refocus 4 --initial-size 2 --iterations 5
      --threads 2)

# Pictures with nothing to trace are refused as `fit` refuses them: one line, exit 2, nothing
# written (a 1x1 picture is all dark or all light).
expect_error "one.png: nothing is outside: no light pixels at 1x1" "$bin" trace "$tmp/one.png" \
  -o "$tmp/out_one" "${tiny[@]}"
expect_error "white.png: nothing is inside: no dark pixels at 24x16" "$bin" trace "$tmp/white.png" \
  -o "$tmp/out_white" "${tiny[@]}"
expect_error "black.png: nothing is outside: no light pixels at 24x16" "$bin" trace \
  "$tmp/black.png" -o "$tmp/out_black" "${tiny[@]}"
expect_error "blank.png: nothing is inside" "$bin" morph "$tmp/disc.png" "$tmp/blank.png" \
  -o "$tmp/out_morph_white" "${tiny[@]}"
expect_error "dark.png: nothing is outside" "$bin" morph "$tmp/dark.png" "$tmp/disc.png" \
  -o "$tmp/out_morph_black" "${tiny[@]}"
for d in out_one out_white out_black out_morph_white out_morph_black; do
  [[ -e "$tmp/$d" ]] && bad "a refused picture left $d" || ok
done
if "$bin" fit "$tmp/white.png" -o "$tmp/fit_white" --iters 1 -q 2>"$tmp/err"; then
  bad "fit accepted white.png"
elif grep -q "nothing is inside" "$tmp/err"; then ok; else bad "fit white.png: $(cat "$tmp/err")"; fi
if "$bin" trace "$tmp/colour.png" -o "$tmp/out_colour" "${tiny[@]}" -q 2>"$tmp/err"; then
  if out=$(check_report "$tmp/out_colour/report.json"); then ok; else bad "trace colour.png report: $out"; fi
else
  bad "trace colour.png: $(cat "$tmp/err")"
fi
# The colour picture is thresholded: the dark disc is set, the light background clear.
if python3 -c 'import json,sys; r=json.load(open(sys.argv[1])); n=r["bitmap"]["pixels_set"]; assert 300 < n < 600, n' \
    "$tmp/out_colour/report.json"; then ok; else bad "colour picture not thresholded"; fi

# Bad input: exit 2, one line naming the file or the flag, nothing written.
expect_error "corrupt.png" "$bin" trace "$tmp/corrupt.png" -o "$tmp/bad1" "${tiny[@]}"
expect_error "no-such.png" "$bin" trace "$tmp/no-such.png" -o "$tmp/bad2" "${tiny[@]}"
expect_error "huge.png.*too large" "$bin" trace "$tmp/huge.png" -o "$tmp/bad3" "${tiny[@]}"
expect_error "^fuzzycsg: error: --population: must be in 1\\.\\.100000" "$bin" trace "$tmp/disc.png" -o "$tmp/bad4" --population 0
expect_error "^fuzzycsg: error: --population: must be in 1\\.\\.100000" "$bin" trace "$tmp/disc.png" -o "$tmp/bad4" --population 100000000
expect_error "^fuzzycsg: error: --k: must be finite and >= 0" "$bin" trace "$tmp/disc.png" -o "$tmp/bad5" --k -1
expect_error "^fuzzycsg: error: --refine-iterations: must be >= 0" "$bin" trace "$tmp/disc.png" -o "$tmp/bad5" --refine --refine-iterations -1
expect_error "--probabilities: all four are zero" "$bin" trace "$tmp/disc.png" -o "$tmp/bad6" \
  --probabilities 0,0,0,0
expect_error "--probabilities: expected four numbers" "$bin" trace "$tmp/disc.png" -o "$tmp/bad7" \
  --probabilities 0.5,0.5
expect_error "--probabilities: \"x\" is not a number" "$bin" trace "$tmp/disc.png" -o "$tmp/bad8" \
  --probabilities 0.5,x,0.1,0.1
expect_error "--probabilities: CUT = -1 is negative" "$bin" trace "$tmp/disc.png" -o "$tmp/bad9" \
  --probabilities 1,1,-1,1
expect_error "--runs" "$bin" trace "$tmp/disc.png" -o "$tmp/bad10" --runs 0
expect_error "cannot create output directory" "$bin" trace "$tmp/disc.png" -o "$tmp/disc.png/sub" "${tiny[@]}"
expect_error "tall.png: 30x40 pixels, but .*disc.png is 40x30" "$bin" morph "$tmp/disc.png" "$tmp/tall.png" \
  -o "$tmp/bad11" "${tiny[@]}"
expect_error "--frames" "$bin" morph "$tmp/disc.png" "$tmp/bar.png" -o "$tmp/bad12" --frames 0
expect_error "--rotation" "$bin" morph "$tmp/disc.png" "$tmp/bar.png" -o "$tmp/bad13" --rotation left
expect_error "corrupt.png" "$bin" morph "$tmp/disc.png" "$tmp/corrupt.png" -o "$tmp/bad14" "${tiny[@]}"
for i in 1 2 3 4 5 6 7 8 9 10 11 12 13 14; do
  if [[ -e "$tmp/bad$i" ]]; then bad "bad input left $tmp/bad$i"; else ok; fi
done

# morph: the trees, the frames, the GIF, the report.
# A program built without giflib (FUZZYCSG_WITH_GIF=OFF) refuses, before it searches or writes.
if [[ ${FUZZYCSG_HAVE_GIFLIB:-1} == 1 ]]; then
  if "$bin" morph "$tmp/disc.png" "$tmp/bar.png" -o "$tmp/m" "${tiny[@]}" --frames 6 --delay 50 \
      --rotation ccw >"$tmp/m.log" 2>&1; then
    ok
    for f in first.json second.json report.json morph.gif frames/frame_000.png frames/frame_005.png; do
      if [[ -s "$tmp/m/$f" ]]; then ok; else bad "morph did not write $f"; fi
    done
    if [[ ! -e "$tmp/m/frames/frame_006.png" ]]; then ok; else bad "morph wrote too many frames"; fi
    if python3 - "$tmp/m" <<'PY'
import json, struct, sys
d = sys.argv[1]
r = json.load(open(d + "/report.json"))
assert r["verb"] == "morph" and r["settings"]["rotation"] == "ccw" and r["settings"]["frames"] == 6
assert r["settings"]["initial_size"] == 2
assert abs(r["score"] - (r["first"]["score"] + r["second"]["score"]) / 2) < 1e-6, "mean"
for t in ("first", "second"):
    x = r[t]
    assert abs(x["score"] - (x["excess"] + x["uncovered"] + x["k"] * x["primitives"])) < 1e-6, t
assert r["first"]["primitives"] == r["second"]["primitives"] == r["primitives"]
assert [f["t"] for f in r["frames"]] == [0, 0.2, 0.4, 0.6, 0.8, 1.0] or \
    max(abs(a - b) for a, b in zip([f["t"] for f in r["frames"]], [0, 0.2, 0.4, 0.6, 0.8, 1])) < 1e-12
# The GIF's blocks: the screen's size, the NETSCAPE2.0 loop extension, one image per frame.
g = open(d + "/morph.gif", "rb").read()
assert g[:6] == b"GIF89a"
w, h, flags = struct.unpack("<HHB", g[6:11])
at = 13 + (3 << ((flags & 7) + 1) if flags & 0x80 else 0)
images, loop = 0, False
def skip_blocks(at):
    while g[at]:
        at += g[at] + 1
    return at + 1
while g[at] != 0x3B:
    if g[at] == 0x21:
        loop = loop or g[at + 3:at + 14] == b"NETSCAPE2.0"
        at = skip_blocks(at + 2)
    else:
        assert g[at] == 0x2C, hex(g[at])
        images += 1
        f = g[at + 9]
        at += 10 + (3 << ((f & 7) + 1) if f & 0x80 else 0)
        at = skip_blocks(at + 1)
assert images == 6, images
assert loop
p = open(d + "/frames/frame_000.png", "rb").read(24)
assert (w, h) == struct.unpack(">II", p[16:24]), (w, h)
assert w >= 256
PY
    then ok; else bad "morph report or GIF"; fi
    if "$bin" info "$tmp/m/first.json" >/dev/null && "$bin" info "$tmp/m/second.json" >/dev/null; then ok; else
      bad "morph trees do not read back"
    fi
    # A shorter morph into the same directory leaves no stale frames behind.
    if "$bin" morph "$tmp/disc.png" "$tmp/bar.png" -o "$tmp/m" "${tiny[@]}" --frames 2 -q &&
        [[ -s "$tmp/m/frames/frame_001.png" && ! -e "$tmp/m/frames/frame_002.png" ]]; then ok; else
      bad "morph: stale frames"
    fi
  else
    bad "morph: $(tail -5 "$tmp/m.log")"
  fi
else
  expect_error "built without giflib" "$bin" morph "$tmp/disc.png" "$tmp/bar.png" -o "$tmp/m" "${tiny[@]}"
  if [[ ! -e "$tmp/m" ]]; then ok; else bad "morph without giflib wrote $tmp/m"; fi
fi

echo "$pass passed, $fail failed"
[[ $fail -eq 0 ]]
