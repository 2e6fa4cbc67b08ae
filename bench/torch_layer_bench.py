#!/usr/bin/python3
"""fuzzycsg.torch's layer (the C++ kernel) against the same model in pure PyTorch
(fuzzycsg.reference), forward + backward on the same batch: B full binary trees of P quadric
leaves with unified operators, each at its own N points, gradients by every input (the points
included). Prints one row per configuration: the median seconds of each over --reps runs (after
one warm-up) and their ratio, with the machine's thread count for both.

    PYTHONPATH=build/release/python /usr/bin/python3 bench/torch_layer_bench.py
    ... --configs 8x512x2048,32x64x4096 --threads 2 --reps 7 --json out.json
"""

import argparse
import json
import os
import platform
import statistics
import time

import torch

from fuzzycsg.torch import CSGLayer


def inputs(layer, b, n, seed=0):
    g = torch.Generator().manual_seed(seed)
    leaf = ((torch.rand(b, layer.leaves, layer.leaf_size, generator=g) - 0.5)).requires_grad_()
    logits = (torch.rand(b, layer.leaves - 1, 4, generator=g) - 0.5).requires_grad_()
    temperature = torch.full((b,), 1000.0).requires_grad_()
    points = (torch.rand(b, n, 3, generator=g) * 2 - 1).requires_grad_()
    return leaf, logits, temperature, points


def step(layer, x, w):
    out = layer(*x)
    return torch.autograd.grad((out * w).sum(), x)


def median_seconds(layer, x, w, reps):
    step(layer, x, w)
    times = []
    for _ in range(reps):
        t0 = time.perf_counter()
        step(layer, x, w)
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--configs", default="8x64x4096,8x512x2048,32x512x512",
                    help="B x P x N, comma separated")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--reps", type=int, default=5)
    ap.add_argument("--json", help="write the rows here too")
    a = ap.parse_args()
    torch.set_num_threads(a.threads)
    rows = []
    print(f"# {platform.processor() or platform.machine()}, {os.cpu_count()} CPUs, "
          f"{a.threads} threads, torch {torch.__version__}, median of {a.reps}")
    print(f"{'B':>4} {'P':>5} {'N':>6} {'kernel s':>10} {'torch s':>10} {'torch/kernel':>13}")
    for config in a.configs.split(","):
        b, p, n = (int(v) for v in config.split("x"))
        kernel = CSGLayer(p, threads=a.threads)
        pure = CSGLayer(p, backend="torch")
        x = inputs(kernel, b, n)
        w = torch.randn(b, n, generator=torch.Generator().manual_seed(1))
        tk = median_seconds(kernel, x, w, a.reps)
        tt = median_seconds(pure, x, w, a.reps)
        rows.append({"B": b, "P": p, "N": n, "threads": a.threads, "kernel_s": tk,
                     "torch_s": tt, "ratio": tt / tk, "torch": torch.__version__})
        print(f"{b:>4} {p:>5} {n:>6} {tk:>10.4f} {tt:>10.4f} {tt / tk:>13.2f}")
    if a.json:
        with open(a.json, "w") as f:
            json.dump(rows, f, indent=1)


if __name__ == "__main__":
    main()
