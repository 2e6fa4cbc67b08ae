#!/usr/bin/python3
"""Fig. 12 at an equal number of primitives: fit the same mesh, tree size and seed with optimised
operator types (unified modes) and with fixed booleans (fixed modes), prune every tree as App. A
says (threshold 1e-3), then, for each pair of a unified and a fixed tree, reduce the one that kept
more primitives to the other's count and compare the errors (MSE on 2 million uniform points) of
the two trees of equal size. The reduction is `fuzzycsg prune --max-primitives` (greedy, the
default) or, with --method threshold, the smallest larger threshold that leaves no more
primitives (found by bisection; a whole subtree goes at once, so it can fall far below the
count). Prints Markdown tables, one row per run and per pair of mesh and size, and with --json
writes every row with both commands; --summary prints the tables of such files again.

  /usr/bin/python3 bench/fig12_equal_size.py --meshes cgal_fandisk.off --prims 64 --seeds 0 \\
      --unified-modes unified,unified-ui --fixed-modes product,godel
"""

import argparse
import json
import math
import os
import re
import statistics
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from fig12_study import MODES, ROOT  # noqa: E402
from data_dir import data_path, require  # noqa: E402

COUNTS = re.compile(r"prune: (\d+)\+(\d+) -> (\d+)\+(\d+) nodes")
MSE = re.compile(r"prune: after\s+MSE ([0-9.eE+-]+)\s+IoU ([0-9.eE+-]+)")


def fit(args, target, prims, mode, seed, out):
    cmd = [args.bin, "fit", target, "-o", out, "--prims", str(prims), "--iters", str(args.iters),
           "--batch", str(args.batch), "--seed", str(seed), "--threads", str(args.threads),
           "--checkpoint-every", "0", "--no-metrics", "-q", *MODES[mode]]
    report_file = os.path.join(out, "report.json")
    # With --keep, a fit already in its directory is read instead of run again (fits are
    # deterministic).
    if not (args.keep and os.path.exists(report_file)):
        subprocess.run(cmd, check=True)
    with open(report_file) as f:
        report = json.load(f)
    shown = " ".join(["fuzzycsg", *cmd[1:]]).replace(out, "OUT")
    return report, shown.replace(" -q", "").replace(" --no-metrics", "")


def prune(args, tree, target, out, metrics, threshold=1e-3, max_primitives=0):
    cmd = [args.bin, "prune", tree, "--target", target, "-o", out, "--threshold",
           f"{threshold:.6g}", "--threads", str(args.threads)]
    if max_primitives:
        cmd += ["--max-primitives", str(max_primitives)]
    if not metrics:
        cmd.append("--no-metrics")
    text = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    kept = int(COUNTS.search(text).group(3))
    m = MSE.search(text) if metrics else None
    return kept, (float(m.group(1)), float(m.group(2))) if m else None


def smallest_threshold(args, tree, target, budget, out):
    # Bisection on log(threshold) for the smallest threshold that keeps at most `budget`
    # primitives; the count falls with the threshold (a larger one removes a superset of nodes
    # in the same post-order, up to ties), checked at the end.
    lo, hi = math.log(1e-3), math.log(1.0)
    if prune(args, tree, target, out, False, math.exp(lo))[0] <= budget:
        return math.exp(lo)
    for _ in range(args.bisections):
        mid = 0.5 * (lo + hi)
        if prune(args, tree, target, out, False, math.exp(mid))[0] <= budget:
            hi = mid
        else:
            lo = mid
    return math.exp(hi)


def reduced(args, tree, target, budget, out):
    """(threshold, kept, MSE) of `tree` reduced to at most `budget` primitives."""
    if args.method == "greedy":
        kept, (mse, _) = prune(args, tree, target, out, True, max_primitives=budget)
        return 1e-3, kept, mse
    threshold = smallest_threshold(args, tree, target, budget, out)
    kept, (mse, _) = prune(args, tree, target, out, True, threshold)
    return threshold, kept, mse


def print_tables(rows, fixed_mode, modes):
    print(f"| mesh | P | seed | unified mode | at 1e-3: unified kept, MSE | {fixed_mode} "
          f"kept, MSE | at equal size: the tree reduced[, threshold], kept, MSE | MSE "
          f"ratio at equal size |")
    print("|---|---:|---:|---|---:|---:|---:|---:|")
    for r in rows:
        cut = "-"
        for side in ("unified", "fixed"):
            if r[side + "_kept"] < r[side + "_kept_default"]:
                threshold = (f', {r[side + "_threshold"]:.3g}'
                             if r.get("method", "threshold") == "threshold" else "")
                cut = f'{side}{threshold}, {r[side + "_kept"]}, {r[side + "_mse"]:.4f}'
        print(f'| {r["mesh"]} | {r["prims"]} | {r["seed"]} | {r["unified_mode"]} | '
              f'{r["unified_kept_default"]}, {r["unified_mse_default"]:.4f} | '
              f'{r["fixed_kept_default"]}, {r["fixed_mse_default"]:.4f} | {cut} | '
              f'{r["unified_mse"] / r["fixed_mse"]:.3f} |')
    # Pair by pair (mesh and size): medians over the seeds.
    print()
    print(f"| mesh | P | unified mode | seeds | median primitives: unified / {fixed_mode} | "
          f"median MSE at equal size: unified / {fixed_mode} | ratio |")
    print("|---|---:|---|---:|---:|---:|---:|")
    pairs = {}
    for r in rows:
        pairs.setdefault((r["mesh"], r["prims"], r["unified_mode"]), []).append(r)
    for (mesh, prims, mode), sel in pairs.items():
        u = statistics.median(r["unified_mse"] for r in sel)
        f = statistics.median(r["fixed_mse"] for r in sel)
        print(f'| {mesh} | {prims} | {mode} | {len(sel)} | '
              f'{statistics.median(r["unified_kept"] for r in sel):g} / '
              f'{statistics.median(r["fixed_kept"] for r in sel):g} | {u:.4f} / {f:.4f} | '
              f'{u / f:.2f} |')
    # Then the geometric mean over the pairs of the ratio of medians.
    print()
    print(f"| unified mode | median MSE below {fixed_mode}'s of the same size | geometric "
          f"mean of median MSE / {fixed_mode}'s of the same size | the same with both "
          f"pruned at 1e-3 |")
    print("|---|---:|---:|---:|")
    for mode in modes:
        pairs = {}
        for r in rows:
            if r["unified_mode"] == mode:
                pairs.setdefault((r["mesh"], r["prims"]), []).append(r)
        below, logs, logs0 = 0, [], []
        for sel in pairs.values():
            u = statistics.median(r["unified_mse"] for r in sel)
            f = statistics.median(r["fixed_mse"] for r in sel)
            u0 = statistics.median(r["unified_mse_default"] for r in sel)
            f0 = statistics.median(r["fixed_mse_default"] for r in sel)
            below += u < f
            logs.append(math.log(u / f))
            logs0.append(math.log(u0 / f0))
        if logs:
            print(f"| {mode} | {below} of {len(logs)} | {math.exp(sum(logs) / len(logs)):.3f} | "
                  f"{math.exp(sum(logs0) / len(logs0)):.3f} |")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--bin", default=os.path.join(ROOT, "build/release/apps/fuzzycsg/fuzzycsg"))
    ap.add_argument("--data", default=data_path("meshes", "cad"))
    ap.add_argument("--meshes", default="cgal_fandisk.off")
    ap.add_argument("--prims", default="32,64,256")
    ap.add_argument("--seeds", default="0,1,2")
    ap.add_argument("--unified-modes", default="unified",
                    help="comma list of modes of fig12_study.py, each against every fixed mode")
    ap.add_argument("--fixed-modes", default="product", help="comma list of modes of fig12_study.py")
    ap.add_argument("--method", choices=["greedy", "threshold"], default="greedy",
                    help="how the larger tree is reduced to the other's size")
    ap.add_argument("--iters", type=int, default=20000)
    ap.add_argument("--batch", type=int, default=1024)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--bisections", type=int, default=8)
    ap.add_argument("--keep", help="keep every fit in this directory (and reuse those found)")
    ap.add_argument("--json", help="also write every row here")
    ap.add_argument("--summary", nargs="+", metavar="JSON",
                    help="fit nothing: print the tables of rows that --json wrote")
    args = ap.parse_args()

    if args.summary:
        rows = [r for f in args.summary for r in json.load(open(f))]
        for fixed in dict.fromkeys(r["fixed_mode"] for r in rows):
            sel = [r for r in rows if r["fixed_mode"] == fixed]
            print_tables(sel, fixed, list(dict.fromkeys(r["unified_mode"] for r in sel)))
        return 0

    for mesh in args.meshes.split(","):
        require(os.path.join(args.data, mesh))
    rows = []
    data = os.path.relpath(os.path.abspath(args.data), ROOT)
    fixed_modes = args.fixed_modes.split(",")
    unified_modes = args.unified_modes.split(",")
    with tempfile.TemporaryDirectory() as tmp:
        work = args.keep or tmp
        for mesh in args.meshes.split(","):
            target = os.path.join(args.data, mesh)
            for prims in [int(p) for p in args.prims.split(",")]:
                for seed in [int(s) for s in args.seeds.split(",")]:
                    base = os.path.join(work, f"{mesh}-{prims}-{seed}")
                    scratch = os.path.join(tmp, f"{mesh}-{prims}-{seed}")
                    fits = {}
                    for mode in fixed_modes + unified_modes:
                        report, cmd = fit(args, target, prims, mode, seed, f"{base}-{mode}")
                        tree = os.path.join(f"{base}-{mode}", "tree.json")
                        # Every tree pruned and measured by `fuzzycsg prune`: the same points
                        # judge redundancy and measure the error.
                        kept, (mse, _) = prune(args, tree, target, f"{scratch}-{mode}.json", True)
                        fits[mode] = (report, cmd.replace(target, os.path.join(data, mesh)),
                                      tree, kept, mse)
                    for fixed in fixed_modes:
                        _, fcmd, ftree, fkept0, fmse0 = fits[fixed]
                        for mode in unified_modes:
                            ur, ucmd, utree, ukept0, umse0 = fits[mode]
                            # The tree that keeps more primitives is reduced to at most the
                            # other's count; the other stays as App. A prunes it.
                            out = scratch + "-equal.json"
                            ut, ukept, umse = 1e-3, ukept0, umse0
                            ft, fkept, fmse = 1e-3, fkept0, fmse0
                            if fkept0 > ukept0:
                                ft, fkept, fmse = reduced(args, ftree, target, ukept0, out)
                            elif ukept0 > fkept0:
                                ut, ukept, umse = reduced(args, utree, target, fkept0, out)
                            rows.append({
                                "mesh": mesh, "prims": prims, "seed": seed,
                                "unified_mode": mode, "fixed_mode": fixed, "method": args.method,
                                "unified_kept_default": ukept0, "unified_mse_default": umse0,
                                "unified_changed": ur["operators"]["changed_type"],
                                "fixed_kept_default": fkept0, "fixed_mse_default": fmse0,
                                "unified_threshold": ut, "unified_kept": ukept,
                                "unified_mse": umse, "fixed_threshold": ft, "fixed_kept": fkept,
                                "fixed_mse": fmse, "unified_command": ucmd, "fixed_command": fcmd,
                            })
                            print(json.dumps(rows[-1]), file=sys.stderr, flush=True)

    for fixed in fixed_modes:
        print_tables([r for r in rows if r["fixed_mode"] == fixed], fixed, unified_modes)
    if args.json:
        with open(args.json, "w") as f:
            json.dump(rows, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
