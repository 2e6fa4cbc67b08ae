#!/usr/bin/python3
"""Medians over seeds of the runs that bench/fig12_study.py wrote with --json, from one or more
such files, one row per mesh, tree size and mode: MSE on 2M uniform points after pruning, IoU,
primitives and nodes after pruning, Chamfer distance, training seconds, and the MSE relative to
a baseline mode of the same mesh and size.

  /usr/bin/python3 bench/fig12_summary.py fig12.json beyond.json --baseline unified \\
      --modes unified,lr3,lr3-reseed
"""

import argparse
import json
import math
import re
import statistics
import sys


def primitives_after(row):
    m = re.search(r"->\s*(\d+)\+(\d+)", row["nodes"])
    return int(m.group(1)) if m else None


def changed(sel):
    # Unified operators whose type differs from the start, of how many ("-" for fixed ones),
    # and in brackets the structure bits that changed (include/fuzzycsg/fit/types.hpp,
    # structure_bits) where the runs recorded them.
    if not all(r.get("unified") for r in sel):
        return "-"
    out = f'{statistics.median(r["changed"] for r in sel):g}/{sel[0]["unified"]}'
    if all(r.get("restructured") is not None for r in sel):
        out += f' ({statistics.median(r["restructured"] for r in sel):g})'
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("files", nargs="+")
    ap.add_argument("--baseline", default="unified", help="mode the MSE ratio is taken against")
    ap.add_argument("--modes", help="comma list: only these modes, in this order")
    ap.add_argument("--versus", help="also compare every mode with this one, pair by pair")
    ap.add_argument("--wins", action="store_true",
                    help="also count, per mode, the mesh and size pairs where its median MSE is "
                         "the lowest of the modes shown")
    args = ap.parse_args()

    rows = []
    for path in args.files:
        with open(path) as f:
            rows.extend(json.load(f))
    modes = args.modes.split(",") if args.modes else []
    for r in rows:
        if r["mode"] not in modes and not args.modes:
            modes.append(r["mode"])
    groups = {}
    for r in rows:
        if r["mode"] in modes:
            groups.setdefault((r["mesh"], r["prims"]), {}).setdefault(r["mode"], []).append(r)

    print("| mesh | P | mode | seeds | median MSE | vs baseline | median IoU | "
          "median primitives kept | median nodes kept | median Chamfer | median types changed | "
          "median train s |")
    print("|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for (mesh, prims) in sorted(groups, key=lambda k: (k[0], k[1])):
        by_mode = groups[(mesh, prims)]
        base = by_mode.get(args.baseline)
        base_mse = statistics.median(r["mse"] for r in base) if base else None
        for mode in modes:
            sel = by_mode.get(mode)
            if not sel:
                continue
            mse = statistics.median(r["mse"] for r in sel)
            ratio = f"{mse / base_mse:.2f}" if base_mse else "-"
            kept = [p for p in (primitives_after(r) for r in sel) if p is not None]
            chamfer = [r["chamfer"] for r in sel if r.get("chamfer") is not None]
            print(f"| {mesh} | {prims} | {mode} | {len(sel)} | {mse:.4f} | {ratio} | "
                  f"{statistics.median(r['iou'] for r in sel):.3f} | "
                  f"{statistics.median(kept) if kept else float('nan'):g} | "
                  f"{statistics.median(r['nodes_after'] for r in sel):g} | "
                  f"{statistics.median(chamfer) if chamfer else float('nan'):.4f} | "
                  f"{changed(sel)} | "
                  f"{statistics.median(r['seconds'] for r in sel):.1f} |")
    if args.versus:
        # Pair by pair (one mesh and size): medians over the seeds, then the geometric mean
        # of the ratios over the pairs, for the error and for the primitives kept after pruning.
        print()
        print(f"| mode | median MSE below {args.versus}'s | geometric mean of median MSE / "
              f"{args.versus}'s | fewer primitives kept than {args.versus} | geometric mean "
              f"of median primitives kept / {args.versus}'s |")
        print("|---|---:|---:|---:|---:|")
        for m in modes:
            if m == args.versus:
                continue
            below, logs, fewer, kept_logs = 0, [], 0, []
            for by_mode in groups.values():
                if m not in by_mode or args.versus not in by_mode:
                    continue
                a = statistics.median(r["mse"] for r in by_mode[m])
                b = statistics.median(r["mse"] for r in by_mode[args.versus])
                below += a < b
                logs.append(math.log(a / b))
                ka = statistics.median(primitives_after(r) for r in by_mode[m])
                kb = statistics.median(primitives_after(r) for r in by_mode[args.versus])
                fewer += ka < kb
                kept_logs.append(math.log(ka / kb))
            if logs:
                print(f"| {m} | {below} of {len(logs)} | {math.exp(sum(logs) / len(logs)):.3f} | "
                      f"{fewer} of {len(logs)} | "
                      f"{math.exp(sum(kept_logs) / len(kept_logs)):.3f} |")
    if args.wins:
        wins = {m: 0 for m in modes}
        pairs = 0
        for key, by_mode in groups.items():
            medians = {m: statistics.median(r["mse"] for r in by_mode[m])
                       for m in modes if m in by_mode}
            if len(medians) < 2:
                continue
            pairs += 1
            wins[min(medians, key=medians.get)] += 1
        print()
        print("| mode | lowest median MSE (of " + str(pairs) + " mesh and size pairs) |")
        print("|---|---:|")
        for m in modes:
            print(f"| {m} | {wins[m]} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
