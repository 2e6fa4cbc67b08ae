#!/usr/bin/python3
"""Fig. 12 as a picture: for each mesh, the primitives kept after pruning (x) against the MSE on 2
million uniform points (y) of every run that bench/fig12_study.py wrote with --json, a colour
per operator mode, a marker per tree size, and each mode's medians over the seeds joined
across the sizes. A run lower and further left is better on both counts. Needs matplotlib
(Debian: python3-matplotlib).

  /usr/bin/python3 bench/fig12_pareto.py docs/fig12.json docs/fig12-union-intersection.json \\
      --modes product,godel,unified,unified-ui -o docs/fig12-pareto.png
"""

import argparse
import json
import re
import statistics
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

COLOURS = ["#2a9d3a", "#d62728", "#1f5fd6", "#17becf", "#9467bd", "#ff7f0e", "#8c564b"]
MARKERS = ["o", "s", "^", "D", "v"]


def primitives_after(row):
    return int(re.search(r"->\s*(\d+)\+", row["nodes"]).group(1))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("files", nargs="+")
    ap.add_argument("--modes", help="comma list: only these modes, in this order")
    ap.add_argument("-o", "--output", required=True, help="PNG to write")
    args = ap.parse_args()

    rows = [r for f in args.files for r in json.load(open(f))]
    modes = args.modes.split(",") if args.modes else list(dict.fromkeys(r["mode"] for r in rows))
    rows = [r for r in rows if r["mode"] in modes]
    if not rows:
        print("fig12_pareto: no runs of these modes", file=sys.stderr)
        return 2
    meshes = list(dict.fromkeys(r["mesh"] for r in rows))
    sizes = sorted({r["prims"] for r in rows})
    cols = min(3, len(meshes))
    nrows = (len(meshes) + cols - 1) // cols
    fig, axes = plt.subplots(nrows, cols, figsize=(4.2 * cols, 3.6 * nrows), squeeze=False)
    for k, mesh in enumerate(meshes):
        ax = axes[k // cols][k % cols]
        for m, mode in enumerate(modes):
            colour = COLOURS[m % len(COLOURS)]
            medians = []
            for s, prims in enumerate(sizes):
                sel = [r for r in rows if (r["mesh"], r["mode"], r["prims"]) == (mesh, mode, prims)]
                if not sel:
                    continue
                xs = [primitives_after(r) for r in sel]
                ys = [r["mse"] for r in sel]
                ax.scatter(xs, ys, s=14, color=colour, marker=MARKERS[s % len(MARKERS)],
                           alpha=0.45, linewidths=0)
                medians.append((statistics.median(xs), statistics.median(ys), s))
            if medians:
                ax.plot([p[0] for p in medians], [p[1] for p in medians], color=colour, lw=1.2,
                        label=mode)
                for x, y, s in medians:
                    ax.scatter([x], [y], s=48, color=colour, marker=MARKERS[s % len(MARKERS)],
                               edgecolors="black", linewidths=0.6, zorder=3)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_title(mesh.replace("cgal_", "").rsplit(".", 1)[0], fontsize=10)
        ax.set_xlabel("primitives kept after pruning", fontsize=8)
        ax.set_ylabel("MSE, 2M uniform points", fontsize=8)
        ax.tick_params(labelsize=7)
        ax.grid(True, which="both", lw=0.3, alpha=0.5)
    for k in range(len(meshes), nrows * cols):
        axes[k // cols][k % cols].axis("off")
    handles, labels = axes[0][0].get_legend_handles_labels()
    size_handles = [plt.Line2D([], [], color="grey", marker=MARKERS[s % len(MARKERS)], ls="",
                               label=f"P = {p}") for s, p in enumerate(sizes)]
    fig.legend(handles + size_handles, labels + [h.get_label() for h in size_handles],
               loc="lower center", ncol=len(handles) + len(size_handles), fontsize=8,
               frameon=False)
    fig.tight_layout(rect=(0, 0.05, 1, 1))
    fig.savefig(args.output, dpi=110)
    return 0


if __name__ == "__main__":
    sys.exit(main())
