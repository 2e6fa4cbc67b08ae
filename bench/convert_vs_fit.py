#!/usr/bin/python3
"""`fuzzycsg convert` against `fuzzycsg fit` with the paper's protocol, shape by shape.

Reads the outputs of scripts/convert-study.sh (OUTDIR/shapes.txt and OUTDIR/<shape>/report.json)
and, for every shape there, runs `fit` as Liu et al. App. A does (quadrics, unified operators,
20,000 steps of 1,024 points, Adam at 1e-3; pruned at 1e-3 as the release does) for each seed,
then `prune --max-primitives K` on the trained tree with K the primitive count `convert` found.
Prints a Markdown table of medians over the seeds: IoU on 2 million uniform points, Chamfer
distance, primitives and seconds. Chamfer distances are in fit's normalised units (the part's
largest half-extent is 0.8); convert's, reported in the mesh's units, are scaled to match.

  /usr/bin/python3 bench/convert_vs_fit.py --study /tmp/fuzzycsg-convert-study \\
      --prims 64 --seeds 0,1,2 --threads 2 --json docs/convert-vs-fit.json
"""

import argparse
import json
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
FIT_PADDING = 0.2  # fit's default: the largest half-extent becomes 1 - padding


def fit(args, mesh, seed, out):
    cmd = [args.bin, "fit", mesh, "-o", out, "--prims", str(args.prims), "--iters", str(args.iters),
           "--batch", "1024", "--lr", "0.001", "--seed", str(seed), "--threads", str(args.threads),
           "--ops", "unified", "--checkpoint-every", "0", "-q"]
    subprocess.run(cmd, check=True)
    with open(os.path.join(out, "report.json")) as f:
        r = json.load(f)
    m = r["metrics"]["pruned"]
    return {"iou": m["iou"], "chamfer": m.get("chamfer"),
            "primitives": r["counts"]["pruned"]["primitives"]}


def prune(args, mesh, tree, k, out):
    cmd = [args.bin, "prune", tree, "--target", mesh, "-o", out, "--max-primitives", str(k),
           "--threads", str(args.threads)]
    start = time.monotonic()
    text = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    seconds = time.monotonic() - start
    after = re.search(r"after\s+MSE \S+\s+IoU (\S+)(?:\s+Chamfer (\S+))?", text)
    counts = re.search(r"-> (\d+)\+", text)
    if not after or not counts:
        sys.exit(f"prune printed no measures for {tree}: {text.strip()}")
    # An empty tree has no Chamfer distance.
    return {"iou": float(after.group(1)),
            "chamfer": float(after.group(2)) if after.group(2) else None,
            "primitives": int(counts.group(1)), "seconds": seconds}


def median(rows, key):
    values = [r[key] for r in rows if r.get(key) is not None]
    return statistics.median(values) if values else None


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--bin", default=os.path.join(ROOT, "build/release/apps/fuzzycsg/fuzzycsg"))
    ap.add_argument("--study", required=True, help="output folder of scripts/convert-study.sh")
    ap.add_argument("--prims", type=int, default=64)
    ap.add_argument("--iters", type=int, default=20000)
    ap.add_argument("--seeds", default="0,1,2")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--json", help="write every run here")
    args = ap.parse_args()
    args.study = os.path.abspath(args.study)
    os.chdir(ROOT)  # the mesh paths of shapes.txt are as convert-study.sh wrote them, from here
    shapes_file = os.path.join(args.study, "shapes.txt")
    if not os.path.exists(shapes_file):
        print(f"{shapes_file}: missing; run scripts/convert-study.sh first", file=sys.stderr)
        sys.exit(2)
    seeds = [int(s) for s in args.seeds.split(",")]
    runs = []
    print(f"| shape | tuned on | convert: IoU / Chamfer / primitives / s | fit {args.prims}, pruned "
          "| fit, `prune --max-primitives` to convert's count |")
    print("|---|---|---|---|---|")
    for line in open(shapes_file):
        name, mesh, known, tuned = line.split()
        report = os.path.join(args.study, name, "report.json")
        if not os.path.exists(report):
            print(f"| {name} | {tuned} | failed | | |")
            continue
        with open(report) as f:
            c = json.load(f)
        scale = c["normalisation"]["scale"] * (1 - FIT_PADDING) / (1 - c["settings"]["padding"])
        chamfer = c["metrics"]["chamfer"]
        conv = {"iou": c["metrics"]["iou"], "chamfer": None if chamfer is None else chamfer * scale,
                "primitives": c["primitives"], "seconds": c["seconds"]["total"]}
        fits, prunes = [], []
        for seed in seeds:
            with tempfile.TemporaryDirectory() as tmp:
                start = time.monotonic()
                f = fit(args, mesh, seed, tmp)
                f["seconds"] = time.monotonic() - start
                p = prune(args, mesh, os.path.join(tmp, "tree.json"), conv["primitives"],
                          os.path.join(tmp, "k.json"))
                p["seconds"] += f["seconds"]  # the tree reduced is the one fit trained
            fits.append(f)
            prunes.append(p)
            runs.append({"shape": name, "seed": seed, "fit": f, "prune_max_primitives": p})
        runs.append({"shape": name, "convert": conv})

        def cell(rows):
            ch = median(rows, "chamfer")
            return "%.4f / %s / %g / %.0f" % (median(rows, "iou"), "-" if ch is None else "%.4f" % ch,
                                              median(rows, "primitives"), median(rows, "seconds"))
        print(f"| {name} | {tuned} | {cell([conv])} | {cell(fits)} | {cell(prunes)} |", flush=True)
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"prims": args.prims, "iters": args.iters, "seeds": seeds, "runs": runs}, f,
                      indent=1)


if __name__ == "__main__":
    main()
