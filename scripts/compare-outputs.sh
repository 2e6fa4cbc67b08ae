#!/usr/bin/env bash
# Runs every verb of two fuzzycsg programs on the examples and the test data, and compares what
# they write: bit for bit, except the fields of reports that record the machine and the clock
# (seconds, timings, command lines, paths). Used to show that a change meant to preserve
# behaviour does.
#
#   scripts/compare-outputs.sh OLD_FUZZYCSG NEW_FUZZYCSG [WORKDIR]
#
# A program built from another commit: git worktree add /tmp/base COMMIT && cmake --preset
# release -S /tmp/base && cmake --build /tmp/base/build/release --target fuzzycsg.
# Prints one line per output that differs and a summary; exits 1 when any differs, 2 on bad use.
set -uo pipefail
if [[ $# -lt 2 || ! -x "$1" || ! -x "$2" ]]; then
  echo "usage: scripts/compare-outputs.sh OLD_FUZZYCSG NEW_FUZZYCSG [WORKDIR]" >&2
  exit 2
fi
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
old=$(realpath "$1")
new=$(realpath "$2")
work=${3:-$(mktemp -d)}
mkdir -p "$work"
ex=$root/examples
data=$root/tests/data

# One command per line: NAME then the arguments; OUT stands for the run's output folder.
commands() {
  cat <<CMDS
info-table info $ex/table.json --json
eval-table eval $ex/table.json --points OUT/../points3.txt -o OUT/occ.txt --grad OUT/grad.json --threads 2
eval-cart eval $ex/cart_2d.json --points OUT/../points2.txt -o OUT/occ.txt --threads 2
mesh-table mesh $ex/table.json -o OUT/table.obj --resolution 64 --threads 2
mesh-box mesh $ex/box_with_hole.json -o OUT/box.ply --resolution 48 --threads 2
mesh-spline mesh $ex/spline_shape.json -o OUT/spline.svg --resolution 96 --threads 2
render-table render $ex/table.json -o OUT/table.png --threads 2
render-cart render $ex/cart_2d.json -o OUT/cart.png --threads 2
diagram-table diagram $ex/table.json -o OUT/table.dot
export-box export $ex/box_with_hole.json -o OUT/box.scad
export-bracket export $ex/extrude_bracket.json -o OUT/bracket.scad
raster-box raster $ex/box_with_hole.json -o OUT/box.png --size 96 -q
raster-csg raster $data/scad/Old/example001.openscad.csg -o OUT/ex1.png --size 96 -q
fit-cart fit $ex/cart_2d.json -o OUT --prims 8 --iters 200 --threads 2 --seed 1 -q --metric-points 20000 --checkpoint-every 0
fit-box fit $ex/box_less_ball.json -o OUT --prims 8 --iters 200 --threads 2 --seed 2 -q --metric-points 20000 --checkpoint-every 0
fit-mesh fit $data/meshes/cad/cgal_cross.off -o OUT --prims 8 --iters 200 --threads 2 --seed 3 -q --metric-points 20000 --checkpoint-every 0
fit-glyph fit $data/glyphs/DejaVuSans-Bold_U0050_P.png -o OUT --prims 8 --iters 200 --threads 2 --seed 4 -q --metric-points 20000 --checkpoint-every 0
prune-cart prune OUT/../fit-cart/tree.json --target $ex/cart_2d.json -o OUT/pruned.json --threads 2 --metric-points 20000
trace-P trace $data/glyphs/DejaVuSans-Bold_U0050_P.png -o OUT --population 12 --max-trees 40 --patience 40 --iterations 10 --threads 2 --seed 3 -q
morph-Pb morph $data/glyphs/DejaVuSans-Bold_U0050_P.png $data/glyphs/DejaVuSerif-Bold_U0062_b.png -o OUT --population 8 --max-trees 20 --patience 20 --iterations 5 --frames 3 --threads 2 --seed 1 -q
refine-csg refine $data/scad/Old/example004.openscad.csg --target $data/scad/Old/example004.ref.off -o OUT --size 32 --views 2 --iters 5 --threads 2 -q
demo-gradient demo --gradient --resolution 16
convert-hole convert $data/meshes/cad/cgal_hole.off -o OUT/conv --seed 3 --threads 2 -q
convert-csg convert $data/scad/Old/example004.openscad.csg -o OUT/conv --threads 2 -q
convert-P convert $data/glyphs/DejaVuSans-Bold_U0050_P.png -o OUT/conv --threads 2 -q
convert-obj convert $data/meshes/cad/cgal_couplingdown.obj -o OUT/conv --threads 2 -q --restarts 1 --resolution 48 --refine-steps 50 --no-tidy
CMDS
}

run_all() {  # BINARY DIR
  local bin=$1 dir=$2
  rm -rf "$dir"
  mkdir -p "$dir"
  printf '0 0 0\n0.3 0.1 -0.2\n0.9 0.9 0.9\n-0.5 0.2 0.4\n' >"$dir/points3.txt"
  printf '0 0\n0.5 -0.3\n-0.9 0.1\n' >"$dir/points2.txt"
  while read -r name args; do
    [[ -z "$name" ]] && continue
    mkdir -p "$dir/$name"
    # shellcheck disable=SC2086
    (cd "$dir/$name" && "$bin" ${args//OUT/$dir/$name} >stdout.txt 2>stderr.txt; echo $? >status.txt)
  done < <(commands)
}

run_all "$old" "$work/old"
run_all "$new" "$work/new"

/usr/bin/python3 - "$work/old" "$work/new" <<'PY'
import json, os, re, sys
old_root, new_root = sys.argv[1], sys.argv[2]
VOLATILE = re.compile(r"seconds|time|command|elapsed|per_second|_s$|path|wrote|host|date")

def scrub(x):
    if isinstance(x, dict):
        # Loss curves are rows [step, loss, seconds]: the clock is dropped.
        return {k: ([row[:2] for row in v] if k in ("curve", "loss_curve") else scrub(v))
                for k, v in x.items() if not VOLATILE.search(k)}
    if isinstance(x, list):
        return [scrub(v) for v in x]
    return x

def same(a, b, name):
    with open(a, "rb") as f: x = f.read()
    with open(b, "rb") as f: y = f.read()
    if x == y:
        return True
    if name.endswith(".json"):
        try:
            return scrub(json.loads(x)) == scrub(json.loads(y))
        except ValueError:
            return False
    if name in ("stdout.txt", "stderr.txt"):  # timings and paths in progress lines
        timed = re.compile(rb"[0-9.]+ ?(s|ms|min)\b")
        norm = lambda t: [b"#" if timed.search(l) else re.sub(rb"/\S*/(old|new)/", b"#", l)
                          for l in t.splitlines()]
        return norm(x) == norm(y)
    return False

differ = compared = 0
for run in sorted(os.listdir(old_root)):
    a_dir, b_dir = os.path.join(old_root, run), os.path.join(new_root, run)
    if not os.path.isdir(a_dir):
        continue
    files = set()
    for d in (a_dir, b_dir):
        for base, _, names in os.walk(d):
            files |= {os.path.relpath(os.path.join(base, n), d) for n in names}
    for rel in sorted(files):
        a, b = os.path.join(a_dir, rel), os.path.join(b_dir, rel)
        compared += 1
        if not (os.path.exists(a) and os.path.exists(b)):
            print(f"{run}/{rel}: only in {'new' if os.path.exists(b) else 'old'}")
            differ += 1
        elif not same(a, b, os.path.basename(rel)):
            print(f"{run}/{rel}: differs")
            differ += 1
print(f"compare-outputs: {compared - differ} of {compared} outputs the same, {differ} differ")
sys.exit(1 if differ else 0)
PY
