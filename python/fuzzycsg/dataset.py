"""A procedural data set of CSG solids, made by fuzzycsg itself, for the generative model of
Liu et al. 2024 §5.3 (``fuzzycsg.generative``).

Each shape is a random tree of 2 to ``max_leaves`` solids — boxes, cylinders, spheres, cones and
tori, placed and turned at random (half of them on the axes) — joined by unions, differences
and intersections, in the spirit of CSGNet's and 3DCSGNet's synthetic sets. A shape is kept when
its solid fills between 3% and 50% of the box [-1, 1]^3 and every leaf changes it (a tree
pruned by fuzzycsg.prune keeps all its leaves). Per shape the set holds:

- ``cloud``: points on the surface (the encoder's input), drawn by area on the tree's mesh;
- ``points``, ``occupancy``: training samples, half uniform in the box, half near the surface
  (surface points moved by N(0, 0.05²) along each axis), labelled inside (1) or outside (0);
- ``eval_points``, ``eval_occupancy``: uniform samples on which the held-out measures are taken;
- ``trees``: the tree file of the shape (JSON text), the ground truth.

The same seed makes the same set, bit for bit:

    python3 -m fuzzycsg.dataset -o data/csg --train 1000 --test 100 --seed 0
"""

from __future__ import annotations

import argparse
import json
import os
import time

import numpy as np

import fuzzycsg

FAMILIES = ("box", "cylinder", "sphere", "cone", "torus")
SHARPNESS = 200.0  # the leaves' sigmoid: the level set within about 1% of the box of the solid


def _leaf(rng: np.random.Generator) -> dict:
    kind = FAMILIES[rng.integers(len(FAMILIES))]
    u = lambda lo, hi: float(rng.uniform(lo, hi))  # noqa: E731
    if kind == "box":
        leaf = {"size": [u(0.25, 1.0), u(0.25, 1.0), u(0.25, 1.0)]}
    elif kind == "cylinder":
        leaf = {"radius": u(0.12, 0.45), "height": u(0.3, 1.1)}
    elif kind == "sphere":
        leaf = {"radius": u(0.2, 0.5)}
    elif kind == "cone":
        leaf = {"radius1": u(0.15, 0.5), "radius2": u(0.0, 0.25), "height": u(0.4, 1.1)}
    else:
        leaf = {"major": u(0.25, 0.5), "minor": u(0.07, 0.18)}
    leaf["type"] = kind
    leaf["translate"] = [u(-0.45, 0.45) for _ in range(3)]
    if rng.uniform() < 0.5:
        leaf["rotate"] = [float(90 * rng.integers(4)) for _ in range(3)]
    else:
        leaf["rotate"] = [u(-45, 45) for _ in range(3)]
    leaf["sharpness"] = SHARPNESS
    return leaf


def random_tree(rng: np.random.Generator, max_leaves: int = 6) -> dict:
    """A random tree file (as a dict) of 2 to ``max_leaves`` solids and min/max booleans."""
    nodes = [_leaf(rng) for _ in range(int(rng.integers(2, max_leaves + 1)))]
    while len(nodes) > 1:
        i, j = rng.choice(len(nodes), 2, replace=False)
        op = ("union", "difference", "intersection")[rng.choice(3, p=(0.5, 0.35, 0.15))]
        joined = {"op": op, "logic": "godel", "children": [nodes[i], nodes[j]]}
        nodes = [n for k, n in enumerate(nodes) if k not in (i, j)] + [joined]
    return {"format": "fuzzycsg-tree", "version": 1, "dim": 3, "root": nodes[0]}


def surface_points(vertices: np.ndarray, triangles: np.ndarray, n: int,
                   rng: np.random.Generator) -> np.ndarray:
    """n points on a triangle mesh, uniform by area."""
    a, b, c = (vertices[triangles[:, k]] for k in range(3))
    area = 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1)
    t = rng.choice(len(triangles), n, p=area / area.sum())
    r1, r2 = rng.uniform(size=(2, n, 1))
    s = np.sqrt(r1)
    return (a[t] * (1 - s) + b[t] * s * (1 - r2) + c[t] * s * r2).astype(np.float32)


def make_shape(rng: np.random.Generator, cloud: int, samples: int, eval_samples: int,
               max_leaves: int = 6):
    """One accepted shape: (tree JSON text, cloud, points, occupancy, eval points, eval
    occupancy)."""
    while True:
        text = json.dumps(random_tree(rng, max_leaves))
        tree = fuzzycsg.Tree.from_json(text)
        probe = rng.uniform(-1, 1, (20000, 3)).astype(np.float32)
        fill = float(np.mean(fuzzycsg.eval(tree, probe, threads=1) >= 0.5))
        if not 0.03 <= fill <= 0.5:
            continue
        _, report = fuzzycsg.prune(tree, probe, threshold=1e-3, threads=1)
        if report["primitives_after"] < report["primitives_before"]:
            continue
        vertices, triangles = fuzzycsg.mesh(tree, resolution=64, threads=1)
        surface = surface_points(vertices, triangles, cloud + samples // 2, rng)
        near = surface[cloud:] + rng.normal(0, 0.05, (samples // 2, 3)).astype(np.float32)
        points = np.concatenate([rng.uniform(-1, 1, (samples - samples // 2, 3)), near])
        points = np.clip(points, -1, 1).astype(np.float32)
        occupancy = (fuzzycsg.eval(tree, points, threads=1) >= 0.5).astype(np.uint8)
        evals = rng.uniform(-1, 1, (eval_samples, 3)).astype(np.float32)
        eval_occupancy = (fuzzycsg.eval(tree, evals, threads=1) >= 0.5).astype(np.uint8)
        return text, surface[:cloud], points, occupancy, evals, eval_occupancy


def make_split(n: int, seed: int, cloud: int = 1024, samples: int = 4096,
               eval_samples: int = 16384, max_leaves: int = 6) -> dict:
    """n shapes drawn with ``seed`` as arrays (see the module's docstring)."""
    rng = np.random.default_rng(seed)
    shapes = [make_shape(rng, cloud, samples, eval_samples, max_leaves) for _ in range(n)]
    names = ("trees", "cloud", "points", "occupancy", "eval_points", "eval_occupancy")
    out = {name: [s[k] for s in shapes] for k, name in enumerate(names)}
    return {k: (np.array(v) if k != "trees" else v) for k, v in out.items()}


def save(split: dict, path: str) -> None:
    arrays = {k: v for k, v in split.items() if k != "trees"}
    arrays["trees"] = np.array(split["trees"])
    tmp = path + ".tmp.npz"
    np.savez_compressed(tmp, **arrays)
    os.replace(tmp, path)


def load(path: str) -> dict:
    with np.load(path) as f:
        split = {k: f[k] for k in f.files}
    split["trees"] = [str(t) for t in split["trees"]]
    return split


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description="Make the procedural CSG data set")
    ap.add_argument("-o", "--output", required=True, help="directory: train.npz, test.npz")
    ap.add_argument("--train", type=int, default=1000)
    ap.add_argument("--test", type=int, default=100)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--max-leaves", type=int, default=6)
    a = ap.parse_args(argv)
    if a.train < 1 or a.test < 1 or a.max_leaves < 2:
        ap.error("--train and --test must be >= 1, --max-leaves >= 2")
    os.makedirs(a.output, exist_ok=True)
    started = time.perf_counter()
    # The two splits come from different streams of one seed: held-out shapes are not in train.
    for name, n, stream in (("train", a.train, 0), ("test", a.test, 1)):
        split = make_split(n, [a.seed, stream], max_leaves=a.max_leaves)
        save(split, os.path.join(a.output, f"{name}.npz"))
    print(f"dataset: {a.train} train and {a.test} test shapes in {a.output} "
          f"({time.perf_counter() - started:.0f} s)")


if __name__ == "__main__":
    main()
