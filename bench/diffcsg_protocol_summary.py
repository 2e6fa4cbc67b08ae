#!/usr/bin/env python3
"""The table of DiffCSG's benchmark protocol from diffcsg_protocol's JSON lines: per method and
perturbation level, the success rate over models and trials, and the median time and steps of
the successful runs; then per model."""
import collections
import json
import statistics
import sys

rows = [json.loads(line) for line in open(sys.argv[1]) if line.strip().startswith("{")]
methods = [m for m in ("diffcsg", "cmaes", "fuzzy") if any(r["method"] == m for r in rows)]
sigmas = sorted({r["sigma"] for r in rows})
size = rows[0]["size"] if rows else 0
print(f"{len({r['model'] for r in rows})} models, {size}x{size} images, "
      f"{len(rows) // max(1, len(methods))} cases per method\n")
print("| method | " + " | ".join(f"σ = {s:g}" for s in sigmas) + " | all |")
print("|---" * (len(sigmas) + 2) + "|")
for m in methods:
    cells = []
    for s in sigmas + [None]:
        rs = [r for r in rows if r["method"] == m and (s is None or r["sigma"] == s)]
        ok = [r for r in rs if r["success"]]
        cells.append(f"{len(ok)}/{len(rs)}" + (f" ({statistics.median(r['seconds'] for r in ok):.1f} s)" if ok else ""))
    print(f"| {m} | " + " | ".join(cells) + " |")
print("\nSuccesses (of trials × σ) per model; the median seconds of the successes in brackets.\n")
models = sorted({r["model"] for r in rows}, key=lambda n: (rows[[r["model"] for r in rows].index(n)]["triangles"], n))
print("| model | triangles | parameters | " + " | ".join(methods) + " |")
print("|---" * (3 + len(methods)) + "|")
for name in models:
    rs = [r for r in rows if r["model"] == name]
    cells = []
    for m in methods:
        mine = [r for r in rs if r["method"] == m]
        ok = [r for r in mine if r["success"]]
        cells.append(f"{len(ok)}/{len(mine)}" + (f" ({statistics.median(r['seconds'] for r in ok):.1f} s)" if ok else ""))
    print(f"| {name.replace('.openscad', '')} | {rs[0]['triangles']} | {rs[0]['parameters']} | " +
          " | ".join(cells) + " |")
