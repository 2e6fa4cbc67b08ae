"""The generative model of Liu et al. 2024 §5.3: a point-cloud autoencoder whose decoder
outputs a fuzzy CSG tree — the parameters of P quadrics and the logits of the P - 1 unified
operators of a full binary tree — decoded to occupancy through fuzzycsg.torch's layer. The
baseline decoder is the same network with fixed operators of product logic (drawn at random
once), as in Liu et al.'s comparisons with fixed booleans.

Commands (the data set is fuzzycsg.dataset's):

    python3 -m fuzzycsg.generative train --data D --decoder unified -o runs/unified --minutes 12
    python3 -m fuzzycsg.generative evaluate --data D --run runs/unified     # Table 1's measures
    python3 -m fuzzycsg.generative pictures --data D --runs runs/unified runs/product -o docs/x

A decoded shape is an ordinary tree (``Autoencoder.trees``): prune, mesh, export it.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import time

import numpy as np
import torch
from torch import nn

import fuzzycsg
from fuzzycsg import dataset as _dataset
from fuzzycsg.torch import CSGLayer


class PointNetEncoder(nn.Module):
    """Shared per-point layers, a max over the points, then a small MLP: a latent code."""

    def __init__(self, latent: int = 256):
        super().__init__()
        self.points = nn.Sequential(
            nn.Conv1d(3, 64, 1), nn.ReLU(), nn.Conv1d(64, 128, 1), nn.ReLU(),
            nn.Conv1d(128, 256, 1), nn.ReLU(), nn.Conv1d(256, latent, 1))
        self.head = nn.Sequential(nn.Linear(latent, latent), nn.ReLU(), nn.Linear(latent, latent))

    def forward(self, cloud: torch.Tensor) -> torch.Tensor:
        return self.head(self.points(cloud.transpose(1, 2)).max(dim=-1).values)


class CSGDecoder(nn.Module):
    """A latent code to the leaves (B x P x 10 quadric coefficients) and, for unified
    operators, the logits (B x (P - 1) x 4) of a full binary tree, evaluated by CSGLayer."""

    def __init__(self, latent: int = 256, leaves: int = 512, ops: str = "unified",
                 sharpness: float = 10.0, seed: int = 0, backend: str = "kernel",
                 threads: int = 0):
        super().__init__()
        self.layer = CSGLayer(leaves, family="quadric", ops=ops, sharpness=sharpness,
                              seed=seed, backend=backend, threads=threads)
        self.body = nn.Sequential(nn.Linear(latent, 512), nn.ReLU(), nn.Linear(512, 1024),
                                  nn.ReLU())
        self.leaf_head = nn.Linear(1024, leaves * self.layer.leaf_size)
        # Each leaf starts near its own random quadric (U[-0.5, 0.5], Liu et al. App. A): the
        # code moves it from there.
        g = torch.Generator().manual_seed(seed)
        with torch.no_grad():
            self.leaf_head.weight.mul_(0.1)
            self.leaf_head.bias.copy_(torch.rand(self.leaf_head.bias.shape, generator=g) - 0.5)
        self.logit_head = None
        if self.layer.unified:
            self.logit_head = nn.Linear(1024, (leaves - 1) * 4)
            with torch.no_grad():
                self.logit_head.weight.mul_(0.1)
                self.logit_head.bias.copy_(torch.rand(self.logit_head.bias.shape,
                                                      generator=g) - 0.5)

    def tree_parameters(self, z: torch.Tensor):
        h = self.body(z)
        leaf = self.leaf_head(h).view(z.shape[0], self.layer.leaves, self.layer.leaf_size)
        logits = None
        if self.logit_head is not None:
            logits = self.logit_head(h).view(z.shape[0], self.layer.leaves - 1, 4)
        return leaf, logits

    def forward(self, z, points, temperature: float):
        leaf, logits = self.tree_parameters(z)
        t = torch.full((z.shape[0],), float(temperature), dtype=leaf.dtype, device=leaf.device)
        return self.layer(leaf, logits, t, points)


class Autoencoder(nn.Module):
    def __init__(self, config: dict):
        super().__init__()
        self.config = dict(config)
        self.encoder = PointNetEncoder(config["latent"])
        self.decoder = CSGDecoder(config["latent"], config["leaves"], config["decoder"],
                                  config["sharpness"], config["seed"],
                                  backend=config.get("backend", "kernel"),
                                  threads=config["threads"])

    def forward(self, cloud, points, temperature):
        return self.decoder(self.encoder(cloud), points, temperature)

    @torch.no_grad()
    def trees(self, z: torch.Tensor, temperature: float) -> list:
        """The decoded trees of codes z (B x latent) as fuzzycsg.Tree objects."""
        leaf, logits = self.decoder.tree_parameters(z)
        return [self.decoder.layer.tree(leaf, logits, temperature, i) for i in range(len(z))]


DEFAULTS = {"decoder": "unified", "leaves": 512, "latent": 256, "sharpness": 10.0,
            "batch": 16, "points": 1024, "cloud": 512, "lr": 1e-3, "minutes": 15.0,
            "steps": 0, "temperature_start": 10.0, "temperature": 1000.0,
            "temperature_ramp": 0.6, "seed": 0, "threads": 0, "device": "cpu",
            "backend": "kernel"}


def temperature_at(config: dict, fraction: float) -> float:
    """The operators' temperature at a fraction of training: geometric from temperature_start to
    temperature over the first temperature_ramp of it (Liu et al.'s ramp), then constant."""
    ramp = config["temperature_ramp"]
    f = 1.0 if ramp <= 0 else min(1.0, fraction / ramp)
    return config["temperature_start"] * (config["temperature"] / config["temperature_start"]) ** f


def _batch(split, index, rng, config, device="cpu"):
    cloud = split["cloud"][index][:, rng.choice(split["cloud"].shape[1], config["cloud"],
                                                replace=False)]
    pick = np.stack([rng.choice(split["points"].shape[1], config["points"], replace=False)
                     for _ in index])
    points = np.take_along_axis(split["points"][index], pick[..., None], axis=1)
    labels = np.take_along_axis(split["occupancy"][index], pick, axis=1)
    to = lambda a: torch.from_numpy(np.ascontiguousarray(a)).float().to(device)  # noqa: E731
    return to(cloud), to(points), to(labels)


def train(data: str, output: str, **overrides) -> dict:
    """Trains for config["minutes"] (or config["steps"] when > 0); writes OUTPUT/model.pt and
    OUTPUT/train.json (config, loss curve, time)."""
    config = {**DEFAULTS, **overrides}
    torch.set_num_threads(config["threads"] or os.cpu_count() or 1)
    torch.manual_seed(config["seed"])
    rng = np.random.default_rng(config["seed"])
    split = _dataset.load(os.path.join(data, "train.npz"))
    device = torch.device(config["device"])
    model = Autoencoder(config).to(device)
    optimiser = torch.optim.Adam(model.parameters(), lr=config["lr"])
    budget = config["minutes"] * 60.0
    started = time.perf_counter()
    curve, step, recent = [], 0, []
    log_every = 50 if config["steps"] <= 0 else max(1, min(50, config["steps"] // 10))
    while True:
        elapsed = time.perf_counter() - started
        fraction = step / config["steps"] if config["steps"] > 0 else elapsed / budget
        if fraction >= 1.0:
            break
        t = temperature_at(config, fraction)
        index = rng.choice(len(split["cloud"]), config["batch"], replace=False)
        cloud, points, labels = _batch(split, index, rng, config, device)
        loss = torch.mean((model(cloud, points, t) - labels) ** 2)
        optimiser.zero_grad()
        loss.backward()
        optimiser.step()
        recent.append(loss.item())
        step += 1
        if step % log_every == 0:
            curve.append([step, float(np.mean(recent)), time.perf_counter() - started, t])
            recent = []
    os.makedirs(output, exist_ok=True)
    _save(model, os.path.join(output, "model.pt"))
    log = {"config": config, "steps": step, "seconds": time.perf_counter() - started,
           "curve": curve, "threads": torch.get_num_threads()}
    _write_json(os.path.join(output, "train.json"), log)
    return log


def _save(model: Autoencoder, path: str) -> None:
    tmp = path + ".tmp"
    state = {k: v.cpu() for k, v in model.state_dict().items()}
    torch.save({"config": model.config, "state": state}, tmp)
    os.replace(tmp, path)


def load_model(run: str) -> Autoencoder:
    """A trained model, on the CPU with the C++ kernel (whatever it was trained on)."""
    saved = torch.load(os.path.join(run, "model.pt"), map_location="cpu")
    model = Autoencoder({**saved["config"], "device": "cpu", "backend": "kernel"})
    model.load_state_dict(saved["state"])
    return model.eval()


def _write_json(path: str, value) -> None:
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        json.dump(value, f, indent=1)
    os.replace(tmp, path)


def occupancy_measures(occupancy: np.ndarray, labels: np.ndarray) -> dict:
    """Table 1's measures for one shape: the MSE of the occupancy, the accuracy of its 0.5
    classification, and the F-score of the inside class."""
    inside = occupancy >= 0.5
    truth = labels.astype(bool)
    tp = float(np.sum(inside & truth))
    precision = tp / max(float(inside.sum()), 1.0)
    recall = tp / max(float(truth.sum()), 1.0)
    f = 0.0 if precision + recall == 0 else 2 * precision * recall / (precision + recall)
    return {"mse": float(np.mean((occupancy - labels) ** 2)),
            "accuracy": float(np.mean(inside == truth)), "fscore": f}


@torch.no_grad()
def evaluate(data: str, run: str, limit: int = 0) -> dict:
    """Table 1's measures on the held-out shapes (mean over shapes), for the decoded fuzzy trees
    and for the same trees snapped and pruned (fuzzycsg.prune on the shape's uniform points),
    with the pruned trees' node counts. Writes RUN/evaluation.json."""
    model = load_model(run)
    config = model.config
    split = _dataset.load(os.path.join(data, "test.npz"))
    n = len(split["cloud"]) if limit <= 0 else min(limit, len(split["cloud"]))
    t = temperature_at(config, 1.0)
    rng = np.random.default_rng(12345)
    fuzzy, pruned, nodes = [], [], []
    for start in range(0, n, 8):
        index = np.arange(start, min(n, start + 8))
        cloud = torch.from_numpy(split["cloud"][index][:, rng.choice(
            split["cloud"].shape[1], config["cloud"], replace=False)])
        z = model.encoder(cloud)
        points = torch.from_numpy(split["eval_points"][index])
        occ = model.decoder(z, points, t).numpy()
        for k, tree in zip(index, model.trees(z, t)):
            labels = split["eval_occupancy"][k].astype(np.float32)
            fuzzy.append(occupancy_measures(occ[k - start], labels))
            small, report = fuzzycsg.prune(tree, split["eval_points"][k], threshold=1e-3)
            pruned.append(occupancy_measures(fuzzycsg.eval(small, split["eval_points"][k]),
                                             labels))
            nodes.append([report["primitives_after"], report["operators_after"]])
    mean = lambda rows, key: float(np.mean([r[key] for r in rows]))  # noqa: E731
    leaves = config["leaves"]
    result = {
        "decoder": config["decoder"], "shapes": n, "leaves": leaves,
        "nodes_before": [leaves, leaves - 1],
        "fuzzy": {k: mean(fuzzy, k) for k in ("mse", "accuracy", "fscore")},
        "pruned": {k: mean(pruned, k) for k in ("mse", "accuracy", "fscore")},
        "nodes_after_mean": [float(np.mean([a for a, _ in nodes])),
                             float(np.mean([b for _, b in nodes]))],
        "nodes_after_max": [int(max(a for a, _ in nodes)), int(max(b for _, b in nodes))],
    }
    _write_json(os.path.join(run, "evaluation.json"), result)
    return result


CAMERA = {"eye": [2.6, -3.4, 2.2], "target": [0.0, 0.0, 0.0], "fov_deg": 30.0}


def _picture(tree, size: int = 200):
    import io

    import matplotlib.image as mpimg

    try:
        png = fuzzycsg.render(tree, camera=CAMERA, width=size, height=size, resolution=96)
    except fuzzycsg.InputError:  # an empty level set: a blank picture
        return np.ones((size, size, 4), np.float32)
    return mpimg.imread(io.BytesIO(png), format="png")


@torch.no_grad()
def pictures(data: str, runs: list, output: str, shapes=(0, 1, 2, 3, 4, 5),
             interpolate=(0, 1), frames: int = 6) -> list:
    """docs pictures: held-out inputs above each run's reconstructions (pruned trees), and a
    latent interpolation between two held-out shapes with the first run's model."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    split = _dataset.load(os.path.join(data, "test.npz"))
    models = [load_model(r) for r in runs]
    os.makedirs(output, exist_ok=True)
    rows = [("held-out input", [_picture(fuzzycsg.Tree.from_json(split["trees"][k]))
                                for k in shapes])]
    for run, model in zip(runs, models):
        cloud = torch.from_numpy(split["cloud"][list(shapes)][:, :model.config["cloud"]])
        trees = model.trees(model.encoder(cloud), temperature_at(model.config, 1.0))
        pics = [_picture(fuzzycsg.prune(t, split["eval_points"][k])[0])
                for k, t in zip(shapes, trees)]
        rows.append((f"{model.config['decoder']} decoder", pics))
    written = [os.path.join(output, "reconstructions.png"), os.path.join(output, "interpolation.png")]
    _grid(plt, rows, written[0])
    model = models[0]
    a, b = interpolate
    cloud = torch.from_numpy(split["cloud"][[a, b]][:, :model.config["cloud"]])
    za, zb = model.encoder(cloud)
    ts = np.linspace(0, 1, frames)
    trees = model.trees(torch.stack([(1 - s) * za + s * zb for s in ts]),
                        temperature_at(model.config, 1.0))
    row = [_picture(fuzzycsg.prune(t, split["eval_points"][a])[0]) for t in trees]
    _grid(plt, [(f"{model.config['decoder']}: code {a} to code {b}", row)], written[1])
    return written


def _grid(plt, rows, path):
    cols = max(len(r[1]) for r in rows)
    fig, axes = plt.subplots(len(rows), cols, figsize=(2 * cols, 2.1 * len(rows)), squeeze=False)
    for i, (label, pics) in enumerate(rows):
        for j in range(cols):
            ax = axes[i][j]
            ax.axis("off")
            if j < len(pics):
                ax.imshow(pics[j])
        axes[i][0].set_title(label, loc="left", fontsize=9)
    fig.tight_layout()
    tmp = path + ".tmp.png"
    fig.savefig(tmp, dpi=100)
    plt.close(fig)
    os.replace(tmp, path)


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description="The generative model of Liu et al. 2024 §5.3")
    sub = ap.add_subparsers(dest="command", required=True)
    tr = sub.add_parser("train")
    tr.add_argument("--data", required=True)
    tr.add_argument("-o", "--output", required=True)
    for key, value in DEFAULTS.items():
        kind = type(value) if not isinstance(value, bool) else int
        tr.add_argument("--" + key.replace("_", "-"), type=kind, default=value)
    # On a GPU: --device cuda --backend torch (the pure-PyTorch model on the device; the kernel
    # backend copies every batch to the CPU and back).
    ev = sub.add_parser("evaluate")
    ev.add_argument("--data", required=True)
    ev.add_argument("--run", required=True)
    ev.add_argument("--limit", type=int, default=0)
    pi = sub.add_parser("pictures")
    pi.add_argument("--data", required=True)
    pi.add_argument("--runs", nargs="+", required=True)
    pi.add_argument("-o", "--output", required=True)
    a = ap.parse_args(argv)
    if a.command == "train":
        overrides = {k: getattr(a, k) for k in DEFAULTS}
        if overrides["decoder"] not in ("unified", "product"):
            ap.error("--decoder: unified or product")
        if overrides["backend"] not in ("kernel", "torch"):
            ap.error("--backend: kernel or torch")
        log = train(a.data, a.output, **overrides)
        print(f"train: {log['steps']} steps in {log['seconds']:.0f} s, loss "
              f"{log['curve'][0][1] if log['curve'] else math.nan:.4f} -> "
              f"{log['curve'][-1][1] if log['curve'] else math.nan:.4f}")
    elif a.command == "evaluate":
        print(json.dumps(evaluate(a.data, a.run, a.limit), indent=1))
    else:
        print("\n".join(pictures(a.data, a.runs, a.output)))


if __name__ == "__main__":
    main()
