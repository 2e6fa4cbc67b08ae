#!/usr/bin/env bash
# DiffCSG's applications (Yuan et al. 2024, §4.4) on examples/table.json, a table whose legs and
# hole are driven by five shared parameters (its hyper-parameters), into docs/diffcsg/:
#   1. direct 3D editing: the table's mesh (meshed by OpenSCAD from `fuzzycsg export`), edited
#      by a script as one would in a modeller (legs pulled 0.2 down, the hole's rim widened 40%),
#      is the target; `refine --shared-only` finds the hyper-parameters that reproduce the edit;
#   2. image-based editing: one colour picture of the table (`raster --colors --save-views`),
#      its legs painted 24 pixels longer, is the target.
# Needs a release build, openscad and python3-pil (installed if missing).
#   scripts/make-diffcsg-examples.sh
set -euo pipefail
cd "$(dirname "$0")/.."
fuzzycsg=build/release/apps/fuzzycsg/fuzzycsg
out=docs/diffcsg
mkdir -p "$out"
if ! /usr/bin/python3 -c 'import PIL' 2>/dev/null; then
  sudo=()
  [[ $(id -u) -ne 0 ]] && sudo=(sudo)
  "${sudo[@]}" apt-get install -y -qq python3-pil >/dev/null
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

echo "== 1. an edited mesh"
"$fuzzycsg" export examples/table.json -o "$tmp/table.scad" --fn 16
openscad -o "$tmp/table.stl" "$tmp/table.scad" 2>/dev/null
/usr/bin/python3 - "$tmp/table.stl" "$tmp/edited.stl" <<'PY'
import math, sys
def edit(x, y, z):
    if z < 0.5:                       # the legs: their feet 0.2 lower, stretched evenly
        z -= 0.2 * (1 - z / 0.5)
    d = math.hypot(x - 0.4, y - 0.1)
    if z > 0.7 and d < 0.16:          # the hole's rim: 40% wider
        x, y = 0.4 + (x - 0.4) * 1.4, 0.1 + (y - 0.1) * 1.4
    return x, y, z
with open(sys.argv[1]) as f, open(sys.argv[2], "w") as g:
    for line in f:
        w = line.split()
        if w and w[0] == "vertex":
            line = "vertex %.9g %.9g %.9g\n" % edit(*map(float, w[1:4]))
        g.write(line)
PY
"$fuzzycsg" refine examples/table.json --target "$tmp/edited.stl" --shared-only -o "$tmp/mesh" \
  --views 4 --random-views 5 --size 256 --iters 600 --lr 0.003 --elevation 20 -q
for f in before target after; do cp "$tmp/mesh/$f.png" "$out/edit-mesh-$f.png"; done
cp "$tmp/mesh/report.json" "$tmp/mesh-report.json"

echo "== 2. an edited picture"
"$fuzzycsg" raster examples/table.json -o "$tmp/view.png" --colors --size 256 --camera 30,20,0 \
  --save-views "$tmp/view.json" -q
/usr/bin/python3 - "$tmp/view.png" <<'PY'
import sys
from PIL import Image
img = Image.open(sys.argv[1]).convert("RGBA")
px = img.load()
w, h = img.size
# The legs' flat colours (primitives 2 to 5 of the palette); antialiased edge pixels are blends.
legs = [(44, 160, 44), (214, 39, 40), (148, 103, 189), (140, 86, 75)]
def leg(c):
    return c[3] > 128 and any(max(abs(c[k] - l[k]) for k in range(3)) <= 2 for l in legs)
for x in range(w):                    # each leg's column: painted 24 pixels further down
    low = None
    for y in range(h):
        if leg(px[x, y]):
            low = y
    if low is not None:
        for y in range(low + 1, min(h, low + 25)):
            px[x, y] = px[x, low]
img.save(sys.argv[1])
PY
cp "$tmp/view.png" "$out/edit-image-target.png"
"$fuzzycsg" refine examples/table.json --target "$tmp/view.json" --shading colours --shared-only \
  -o "$tmp/image" --iters 600 --lr 0.003 -q
for f in before after; do cp "$tmp/image/$f.png" "$out/edit-image-$f.png"; done

/usr/bin/python3 - "$tmp/mesh-report.json" "$tmp/image/report.json" <<'PY'
import json, sys
for name, path in zip(["edited mesh", "edited picture"], sys.argv[1:]):
    r = json.load(open(path))
    moved = {p["name"]: (p["before"], p["after"]) for p in r["parameters"]
             if p["name"] in ("leg_height", "leg_z", "leg_radius", "hole_radius", "top_thickness")}
    print(f"{name}: {r['steps']} steps, {r['seconds']:.1f} s, converged {r['converged']}; " +
          ", ".join(f"{k} {a:.3f} -> {b:.3f}" for k, (a, b) in sorted(moved.items())))
PY

echo "== 3. gradient images"
# DiffCSG Fig. 9: the colour image's derivative with respect to the subtracted ball's x
# position, by the renderer's gradients with and without intersection-edge antialiasing, and by
# central differences; all on one colour scale.
for mode in analytic no-aa fd; do
  args=()
  [[ $mode == no-aa ]] && args=(--no-intersection-aa)
  [[ $mode == fd ]] && args=(--finite-difference 3e-3)
  "$fuzzycsg" raster examples/box_less_ball.json -o "$out/gradient-ball-x-$mode.png" --size 256 \
    --camera 40,35,0 --colors --gradient "root.children[1].translate[0]" --gradient-scale 20 \
    "${args[@]}"
done
"$fuzzycsg" raster examples/box_less_ball.json -o "$out/gradient-ball-model.png" --shaded \
  --size 256 --camera 40,35,0 -q
# DiffCSG Fig. 1: per-parameter gradients of a program's loss against an edited target (the
# edited picture of part 2), one picture per hyper-parameter.
for p in leg_height hole_radius; do
  "$fuzzycsg" raster examples/table.json -o "$out/gradient-table-$p.png" --colors --size 256 \
    --camera 30,20,0 --gradient "$p" --target "$tmp/view.json"
done
