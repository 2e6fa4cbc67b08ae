#!/usr/bin/python3
"""Liu et al. 2024, Fig. 12: optimising the operator types (unified B_c) against fixed, randomly
initialised booleans with product logic and with Gödel logic, on CAD meshes, for several tree
sizes and seeds. Runs `fuzzycsg fit` for every combination and prints a Markdown table: occupancy
MSE on 2 million uniform points after pruning, IoU, node counts before -> after pruning and the
number of unified operators whose type changed, each row with its command, then medians over
the seeds.

  /usr/bin/python3 bench/fig12_study.py --bin build/release/apps/fuzzycsg/fuzzycsg \\
      --meshes cgal_fandisk.off --prims 32,64,256 --seeds 0,1 --iters 20000

Modes: "unified" (our default: the temperature rises from 10 to 1000 over the first 30% of the steps),
"unified-t1000" (t = 1000 from the first step, as App. A reads), "product", "godel"; the
variants of docs/results.md: "unified-balanced" and "unified-t1000-balanced" (--op-init balanced),
"lr3*" (lr 3e-3, re-seeding, starts from the target), "lr3-product*" (the same with product
booleans), "ts*" (the search over operator types), "*-log" (Adam steps log sharpness), "*-sphere" and "*-circle" (balls and discs
instead of quadrics and conics), "mix" (mixed primitive families). --data and --meshes take
pictures as well (docs/results.md, "Fig. 12 in 2D").
"""

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from data_dir import data_path, require  # noqa: E402

MODES = {
    "unified": ["--ops", "unified"],
    "unified-t1000": ["--ops", "unified", "--temperature-ramp", "0"],
    "product": ["--ops", "product"],
    "godel": ["--ops", "godel"],
    # Unified operators whose types start as the fixed baselines' do (a third each of union,
    # intersection, difference) instead of App. A's uniform logits (a difference half the time).
    "unified-balanced": ["--ops", "unified", "--op-init", "balanced"],
    "unified-t1000-balanced": ["--ops", "unified", "--op-init", "balanced",
                               "--temperature-ramp", "0"],
    # Beyond the paper (docs/results.md): a larger step, re-seeding of dead primitives, and
    # initialisation from the target.
    "lr3": ["--ops", "unified", "--lr", "3e-3"],
    "lr3-reseed": ["--ops", "unified", "--lr", "3e-3", "--reseed-every", "1000"],
    "lr3-reseed-surface": ["--ops", "unified", "--lr", "3e-3", "--reseed-every", "1000",
                           "--init", "surface"],
    "lr3-balls": ["--ops", "unified", "--lr", "3e-3", "--init", "balls"],
    # The same changes with fixed product booleans, so that re-seeding is compared fairly.
    "lr3-product": ["--ops", "product", "--lr", "3e-3"],
    "lr3-product-reseed": ["--ops", "product", "--lr", "3e-3", "--reseed-every", "1000"],
    # Search over the operator types (fuzzycsg/fit/types.hpp).
    "ts": ["--ops", "unified", "--temperature-ramp", "0", "--type-search-every", "500"],
    "ts-balanced": ["--ops", "unified", "--temperature-ramp", "0", "--type-search-every", "500",
                    "--op-init", "balanced"],
    "ts-ramp": ["--ops", "unified", "--type-search-every", "500"],
    "ts-late-balanced": ["--ops", "unified", "--temperature-ramp", "0", "--op-init", "balanced",
                         "--type-search-every", "500", "--type-search-from", "0.5"],
    "ts-late": ["--ops", "unified", "--temperature-ramp", "0",
                "--type-search-every", "500", "--type-search-from", "0.5"],
    "ts-few": ["--ops", "unified", "--temperature-ramp", "0", "--type-search-every", "500",
               "--type-search-switches", "4"],
    "ts-reseed": ["--ops", "unified", "--temperature-ramp", "0", "--type-search-every", "500",
                  "--reseed-every", "1000"],
    "t1000-reseed": ["--ops", "unified", "--temperature-ramp", "0", "--reseed-every", "1000"],
    "product-reseed": ["--ops", "product", "--reseed-every", "1000"],
    "lr3-ts-reseed": ["--ops", "unified", "--lr", "3e-3", "--temperature-ramp", "0",
                      "--type-search-every", "500", "--reseed-every", "1000"],
    # Unified operators that are unions or intersections only (--op-types): with quadric
    # leaves a difference is an intersection with a negated leaf (fuzzycsg/fit/types.hpp).
    "unified-ui": ["--ops", "unified", "--op-types", "union-intersection"],
    # Both started from the target (--init surface), so that the comparison of optimised and
    # fixed types is not one of two random starts.
    "unified-ui-surface": ["--ops", "unified", "--op-types", "union-intersection",
                           "--init", "surface"],
    "product-surface": ["--ops", "product", "--init", "surface"],
    "ts-ui": ["--ops", "unified", "--op-types", "union-intersection", "--temperature-ramp", "0",
              "--type-search-every", "500"],
    # The same from a temperature of 1, where a two-type operator starts as a blend of union
    # and intersection (their mean is the average (x + y) / 2) and hardens over the ramp.
    "ui-t1": ["--ops", "unified", "--op-types", "union-intersection", "--temperature-start", "1"],
    "ui-t1-r5": ["--ops", "unified", "--op-types", "union-intersection", "--temperature-start", "1",
                 "--temperature-ramp", "0.5"],
    # Adam steps the logarithm of each leaf's sharpness (--sharpness-param log), the same
    # change for the unified operators and the fixed baselines.
    "unified-log": ["--ops", "unified", "--sharpness-param", "log"],
    "unified-ui-log": ["--ops", "unified", "--op-types", "union-intersection",
                       "--sharpness-param", "log"],
    "product-log": ["--ops", "product", "--sharpness-param", "log"],
    "godel-log": ["--ops", "godel", "--sharpness-param", "log"],
    # Balls instead of quadrics: a leaf cannot become its own complement.
    "unified-sphere": ["--ops", "unified", "--family", "sphere"],
    "product-sphere": ["--ops", "product", "--family", "sphere"],
    "godel-sphere": ["--ops", "godel", "--family", "sphere"],
    "ts-sphere": ["--ops", "unified", "--temperature-ramp", "0", "--type-search-every", "500",
                  "--family", "sphere"],
    # The same in 2D: discs instead of conics.
    "unified-circle": ["--ops", "unified", "--family", "circle"],
    "product-circle": ["--ops", "product", "--family", "circle"],
    "godel-circle": ["--ops", "godel", "--family", "circle"],
    "ts-circle": ["--ops", "unified", "--temperature-ramp", "0", "--type-search-every", "500",
                  "--family", "circle"],
    # Primitive families mixed (quadric, sphere, box, cylinder in turn).
    "mix": ["--ops", "unified", "--family", "mix"],
    "lr3-reseed-mix": ["--ops", "unified", "--lr", "3e-3", "--reseed-every", "1000",
                       "--family", "mix"],
}


ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def run(args, mesh, prims, mode, seed, out):
    cmd = [args.bin, "fit", os.path.join(args.data, mesh), "-o", out, "--prims", str(prims),
           "--iters", str(args.iters), "--batch", str(args.batch),
           *([] if "--lr" in MODES[mode] else ["--lr", str(args.lr)]), "--seed", str(seed), "--threads", str(args.threads), "--checkpoint-every", "0", "-q",
           *MODES[mode]]
    subprocess.run(cmd, check=True)
    with open(os.path.join(out, "report.json")) as f:
        report = json.load(f)
    data = os.path.relpath(os.path.abspath(args.data), ROOT)
    shown = " ".join(["fuzzycsg", *cmd[1:2], os.path.join(data, mesh), *cmd[3:]])
    shown = shown.replace(" -q", "").replace(" --checkpoint-every 0", "")
    return report, shown.replace(out, "OUT")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    root = ROOT
    ap.add_argument("--bin", default=os.path.join(root, "build/release/apps/fuzzycsg/fuzzycsg"))
    ap.add_argument("--data", default=data_path("meshes", "cad"))
    ap.add_argument("--meshes", default="cgal_fandisk.off")
    ap.add_argument("--prims", default="32,64,256")
    ap.add_argument("--modes", default="unified,unified-t1000,product,godel")
    ap.add_argument("--seeds", default="0,1")
    ap.add_argument("--iters", type=int, default=20000)
    ap.add_argument("--batch", type=int, default=1024)
    ap.add_argument("--lr", type=float, default=1e-3)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--json", help="also write every run's summary here")
    args = ap.parse_args()
    for mesh in args.meshes.split(","):
        require(os.path.join(args.data, mesh))

    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for mesh in args.meshes.split(","):
            for prims in [int(p) for p in args.prims.split(",")]:
                for mode in args.modes.split(","):
                    for seed in [int(s) for s in args.seeds.split(",")]:
                        out = os.path.join(tmp, f"{mesh}-{prims}-{mode}-{seed}")
                        r, cmd = run(args, mesh, prims, mode, seed, out)
                        c0, c1 = r["counts"]["trained"], r["counts"]["pruned"]
                        rows.append({
                            "mesh": mesh, "prims": prims, "mode": mode, "seed": seed,
                            "mse": r["metrics"]["pruned"]["mse"],
                            "mse_trained": r["metrics"]["trained"]["mse"],
                            "iou": r["metrics"]["pruned"]["iou"],
                            "chamfer": r["metrics"]["pruned"].get("chamfer"),
                            "nodes": f'{c0["primitives"]}+{c0["operators"]} -> '
                                     f'{c1["primitives"]}+{c1["operators"]}',
                            "nodes_after": c1["primitives"] + c1["operators"],
                            "changed": r["operators"]["changed_type"],
                            "restructured": r["operators"].get("changed_structure"),
                            "unified": r["operators"]["unified"],
                            "switches": r["operators"].get("type_switches", 0),
                            "seconds": r["timings"]["train_seconds"],
                            "command": cmd,
                        })
                        print(json.dumps(rows[-1]), file=sys.stderr, flush=True)

    print("| mesh | P | operators | seed | MSE (2M pts) | IoU | nodes before -> after | "
          "types changed | train s | command |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        changed = f'{r["changed"]}/{r["unified"]}' if r["unified"] else "-"
        print(f'| {r["mesh"]} | {r["prims"]} | {r["mode"]} | {r["seed"]} | {r["mse"]:.4f} | '
              f'{r["iou"]:.3f} | {r["nodes"]} | {changed} | {r["seconds"]:.1f} | '
              f'`{r["command"]}` |')
    print()
    print("| mesh | P | operators | median MSE | median IoU | median nodes after pruning |")
    print("|---|---|---|---|---|---|")
    keys = []
    for r in rows:
        k = (r["mesh"], r["prims"], r["mode"])
        if k not in keys:
            keys.append(k)
    for k in keys:
        sel = [r for r in rows if (r["mesh"], r["prims"], r["mode"]) == k]
        print(f'| {k[0]} | {k[1]} | {k[2]} | {statistics.median(r["mse"] for r in sel):.4f} | '
              f'{statistics.median(r["iou"] for r in sel):.3f} | '
              f'{statistics.median(r["nodes_after"] for r in sel):g} |')
    if args.json:
        with open(args.json, "w") as f:
            json.dump(rows, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
