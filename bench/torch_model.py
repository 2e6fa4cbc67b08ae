#!/usr/bin/python3
"""The fuzzy CSG model of Liu et al. 2024 (App. A) in plain PyTorch, on the CPU: the baseline
the fuzzycsg evaluator is measured against, and an autograd reference for its gradients.

Model: a full binary tree of P quadric leaves and P - 1 unified operators.
  leaf       f = q0 x² + q1 y² + q2 z² + q3 xy + q4 yz + q5 zx + q6 x + q7 y + q8 z + q9  (eq. 18-19)
             in 2D (the release's 2D case): f = q0 x² + q1 y² + q2 xy + q3 x + q4 y + q5
             o = 1 / (1 + exp(s f))         (eq. 20 with f negative inside: sigmoid(-s f))
  operator   B_c(x, y) = (c1 + c2) x + (c1 + c3) y + (c0 - c1 - c2 - c3) x y       (eq. 12)
             c = softmax(sin(omega * logits) * t),  t = 1000, omega = 10             (eq. 21)
  loss       mean over points of (o_root - target)²
Layout (what a tuned PyTorch implementation of the paper does): all leaves at once, monomials
M [10, N] and the leaf matrix Q [P, 10] (2D: [6, N] and [P, 6]; sharpness folded in:
-s f = (-s Q) M over [P, N], as nine (2D: five) broadcast multiply-adds, or one matmul with
--leaf matmul; then one sigmoid); then layer by
layer, the [K, N] node values viewed as [K/2, 2, N] and split with unbind so that the two
children of every node of the next layer are contiguous rows, each layer's operator written as
two fused multiply-adds (B = x (a + g y) + b y with torch.addcmul). float32, contiguous, no Python loop over nodes; gradients of every parameter with torch.autograd.grad.

Commands
  bench     time forward+backward (median of --reps after --warmup) for the P x N x threads
            grid; prints one JSON line per configuration:
            {"impl":"torch","P":..,"N":..,"threads":..,"median_s":..,"leaf_points_per_s":..,...}
  train     time S steps of training as the authors' release does it (torch.optim.Adam on the
            MSE of batches of N points, 2D or 3D, median of --reps runs of S steps after
            --warmup steps); prints one JSON line:
            {"impl":"torch","mode":"train","dim":..,"P":..,"batch":..,"steps":..,"threads":..,
             "seconds":..,"seconds_per_step":..,"final_loss":..,"torch":..,...}
  grad      loss, gradient and occupancy of a case file written by `eval_bench --dump-case`
            (format in check_against_torch.py), as JSON.
  selftest  checks the layer-by-layer model (3D and 2D) against a direct recursive evaluation of
            the tree (float64), autograd against finite differences (torch.autograd.gradcheck),
            and that a train step moves the parameters.

Run with Debian's interpreter: /usr/bin/python3 bench/torch_model.py bench --threads 1,2
                               /usr/bin/python3 bench/torch_model.py train --dim 2 --P 128
"""

import argparse
import json
import math
import os
import statistics
import sys
import time

import torch

MONOMIALS = ("x^2", "y^2", "z^2", "xy", "yz", "zx", "x", "y", "z", "1")  # eq. 18-19 order
MONOMIALS_2D = ("x^2", "y^2", "xy", "x", "y", "1")  # the release's 2D quadric
TEMPERATURE = 1000.0
OMEGA = 10.0
TARGET_RADIUS = 0.6
# Default slice of the benchmark: [P, chunk] float32 temporaries of about 8 MiB. Whole batches
# of [P, N] (256 MiB at P = 1024, N = 65536) run several times slower (allocation and cache
# misses); much smaller slices pay Python and dispatch overhead per operation.
AUTO_CHUNK_ELEMENTS = 1 << 21


# ---- the model ---------------------------------------------------------------------------


def monomials(points):
    """points [N, 3] -> M [10, N], rows in MONOMIALS order; points [N, 2] -> M [6, N], rows in
    MONOMIALS_2D order."""
    p = points.t()
    if p.shape[0] == 2:
        x, y = p[0], p[1]
        return torch.stack((x * x, y * y, x * y, x, y, torch.ones_like(x)))
    x, y, z = p[0], p[1], p[2]
    return torch.stack((x * x, y * y, z * z, x * y, y * z, z * x, x, y, z, torch.ones_like(x)))


def _column(v):
    """A per-node scalar (float, or tensor [K]) as something that broadcasts against [K, 4]."""
    return v.unsqueeze(1) if torch.is_tensor(v) and v.dim() == 1 else v


def unified_weights(logits, t, omega):
    """c = softmax(sin(omega * logits) * t) per row of logits [K, 4] (eq. 21)."""
    return torch.softmax(torch.sin(_column(omega) * logits) * _column(t), dim=1)


def leaf_values(M, Q, s, leaf="elementwise"):
    """-s f for every leaf and point, [P, N]: the sigmoid argument of o = 1 / (1 + exp(s f)).

    "matmul": one (-s Q) @ M. "elementwise": the same sum as nine (2D: five) broadcast
    multiply-adds (addcmul) over [P, N]; faster than the matmul where PyTorch links the
    reference BLAS (K = 10 is far too small for a BLAS to shine anyway), and what the benchmark
    uses. The last monomial is the constant 1.
    """
    A = Q * (-s).unsqueeze(1)
    if leaf == "matmul":
        return A @ M
    last = Q.shape[1] - 1
    z = torch.addcmul(A[:, last:last + 1], A[:, 0:1], M[0])
    for j in range(1, last):
        z = z.addcmul_(A[:, j:j + 1], M[j])
    return z


def tree_occupancy(M, Q, s, layers, leaf="elementwise"):
    """Root occupancy [N].

    M [10, N] monomials (2D: [6, N]); Q [P, 10] leaf coefficients (2D: [P, 6]), leaves left to
    right; s [P] sharpness;
    layers: bottom-up list of (logits [K, 4], t, omega) with K = P/2, P/4, ..., 1, nodes left to
    right, where node k of a layer combines nodes 2k (x) and 2k + 1 (y) of the layer below.
    """
    O = torch.sigmoid(leaf_values(M, Q, s, leaf))  # 1 / (1 + exp(s f)), [P, N]
    for logits, t, omega in layers:
        c = unified_weights(logits, t, omega)
        k = c.shape[0]
        a = (c[:, 1] + c[:, 2]).unsqueeze(1)
        b = (c[:, 1] + c[:, 3]).unsqueeze(1)
        g = (c[:, 0] - c[:, 1] - c[:, 2] - c[:, 3]).unsqueeze(1)
        pairs = O.view(k, 2, -1)
        x, y = pairs.unbind(1)
        O = torch.addcmul(b * y, x, torch.addcmul(a, g, y))  # a x + b y + g x y
    assert O.shape[0] == 1, "layers must reduce the leaves to one root"
    return O[0]


def mse(o, targets):
    return torch.mean((o - targets) ** 2)


# ---- benchmark ---------------------------------------------------------------------------


class PaperModel:
    """Parameters as the paper initializes them: U[-0.5, 0.5], sharpness 1 (quadric default).
    dim 3: 3D quadrics (10 coefficients); dim 2: 2D quadrics (6 coefficients); the per-leaf
    sharpness s is the 2D release's per-leaf scaling."""

    def __init__(self, leaves, seed=0, dtype=torch.float32, dim=3):
        if leaves < 2 or leaves & (leaves - 1):
            raise ValueError("leaves must be a power of two >= 2")
        if dim not in (2, 3):
            raise ValueError("dim must be 2 or 3")
        self.dim = dim
        gen = torch.Generator().manual_seed(seed)

        def uniform(*shape):
            return (torch.rand(*shape, generator=gen, dtype=dtype) - 0.5).requires_grad_()

        self.Q = uniform(leaves, 10 if dim == 3 else len(MONOMIALS_2D))
        self.s = torch.ones(leaves, dtype=dtype).requires_grad_()
        self.logits = []
        k = leaves // 2
        while k >= 1:
            self.logits.append(uniform(k, 4))
            k //= 2

    def parameters(self):
        return [self.Q, self.s, *self.logits]

    def loss_and_grad(self, points, targets, chunk=0, leaf="elementwise",
                      temperature=TEMPERATURE, omega=OMEGA):
        """MSE loss and the gradient of every parameter. chunk > 0 processes the points in
        slices of that size (the loss is a mean, so slice gradients add up to the full one)."""
        params = self.parameters()
        layers = [(l, temperature, omega) for l in self.logits]
        n = points.shape[0]
        if chunk <= 0 or chunk >= n:
            loss = mse(tree_occupancy(monomials(points), self.Q, self.s, layers, leaf), targets)
            return loss, torch.autograd.grad(loss, params)
        total, grads = 0.0, None
        for i in range(0, n, chunk):
            p, t = points[i:i + chunk], targets[i:i + chunk]
            o = tree_occupancy(monomials(p), self.Q, self.s, layers, leaf)
            part = torch.sum((o - t) ** 2) / n
            g = torch.autograd.grad(part, params)
            grads = list(g) if grads is None else [a + b for a, b in zip(grads, g)]
            total += part.item()
        return torch.tensor(total), grads


def make_points(n, seed, dtype=torch.float32, dim=3):
    """n points uniform in [-1, 1]^dim and their targets: 1 inside the ball (disc) of radius
    TARGET_RADIUS, else 0."""
    gen = torch.Generator().manual_seed(seed)
    points = torch.rand(n, dim, generator=gen, dtype=dtype) * 2 - 1
    targets = ((points * points).sum(1) < TARGET_RADIUS**2).to(dtype)
    return points, targets


def bench(args):
    interop_set = False
    for leaves in args.P:
        model = PaperModel(leaves, seed=args.seed)
        for n in args.N:
            points, targets = make_points(n, args.seed + 1)
            chunk = args.chunk if args.chunk >= 0 else max(256, AUTO_CHUNK_ELEMENTS // leaves)
            chunk = 0 if chunk >= n else chunk
            for threads in args.threads:
                torch.set_num_threads(threads)
                if not interop_set:
                    torch.set_num_interop_threads(1)
                    interop_set = True
                for _ in range(args.warmup):
                    model.loss_and_grad(points, targets, chunk, args.leaf)
                times = []
                while len(times) < args.reps or (sum(times) < args.min_time and
                                                 len(times) < 1000):
                    t0 = time.perf_counter()
                    loss, _ = model.loss_and_grad(points, targets, chunk, args.leaf)
                    times.append(time.perf_counter() - t0)
                med = statistics.median(times)
                print(json.dumps({
                    "impl": "torch", "P": leaves, "N": n, "threads": threads,
                    "median_s": med, "leaf_points_per_s": leaves * n / med,
                    "reps": len(times), "min_s": min(times), "chunk": chunk or n,
                    "leaf": args.leaf,
                    "loss": float(loss), "torch": torch.__version__,
                    "glibc_tunables": os.environ.get("GLIBC_TUNABLES", ""),
                }), flush=True)


# ---- training (the authors' release: torch.optim.Adam on the MSE of point batches) ---------


def train_steps(model, optimizer, batches, first_step, steps, resample_every, chunk=0,
                leaf="elementwise", temperature=TEMPERATURE, omega=OMEGA):
    """Steps first_step .. first_step + steps - 1 of Adam on the MSE; step i uses the
    pre-generated batch (i // resample_every) mod len(batches), i.e. fresh points every
    resample_every steps. Returns the loss of the last step (a 0-d tensor)."""
    params = model.parameters()
    loss = None
    for i in range(first_step, first_step + steps):
        points, targets = batches[(i // resample_every) % len(batches)]
        loss, grads = model.loss_and_grad(points, targets, chunk, leaf, temperature, omega)
        for p, g in zip(params, grads):
            p.grad = g
        optimizer.step()
    return loss


def train(args):
    for name in ("P", "batch", "steps", "threads", "reps", "batches", "resample_every"):
        if getattr(args, name) < 1:
            raise SystemExit(f"error: --{name.replace('_', '-')} must be at least 1")
    if args.warmup < 0:
        raise SystemExit("error: --warmup must be at least 0")
    torch.set_num_threads(args.threads)
    torch.set_num_interop_threads(1)
    try:
        model = PaperModel(args.P, seed=args.seed, dim=args.dim)
    except ValueError as e:
        raise SystemExit(f"error: --P: {e}")
    optimizer = torch.optim.Adam(model.parameters(), lr=args.lr)
    # Sampling is not what is compared: the point batches are drawn before timing and cycled.
    batches = [make_points(args.batch, args.seed + 1 + b, dim=args.dim)
               for b in range(args.batches)]
    chunk = args.chunk if args.chunk >= 0 else max(256, AUTO_CHUNK_ELEMENTS // args.P)
    chunk = 0 if chunk >= args.batch else chunk
    common = dict(resample_every=args.resample_every, chunk=chunk, leaf=args.leaf,
                  temperature=args.temperature, omega=args.omega)
    step = 0
    loss = train_steps(model, optimizer, batches, step, args.warmup, **common)
    step += args.warmup
    times = []
    for _ in range(args.reps):
        t0 = time.perf_counter()
        loss = train_steps(model, optimizer, batches, step, args.steps, **common)
        times.append(time.perf_counter() - t0)
        step += args.steps
    med = statistics.median(times)
    print(json.dumps({
        "impl": "torch", "mode": "train", "dim": args.dim, "P": args.P, "batch": args.batch,
        "steps": args.steps, "threads": args.threads, "seconds": med,
        "seconds_per_step": med / args.steps, "final_loss": float(loss),
        "torch": torch.__version__,
        "reps": args.reps, "seconds_all": times,
        "seconds_per_step_all": [t / args.steps for t in times],
        "warmup": args.warmup, "temperature": args.temperature, "omega": args.omega,
        "lr": args.lr, "resample_every": args.resample_every, "batches": args.batches,
        "chunk": chunk or args.batch, "leaf": args.leaf, "seed": args.seed,
        "glibc_tunables": os.environ.get("GLIBC_TUNABLES", ""),
    }), flush=True)


# ---- case files (cross-check with the C++ evaluator) -------------------------------------


def case_structure(case):
    """Leaves left to right and the inner nodes layer by layer (bottom-up, left to right) of the
    full binary tree in a case file; raises ValueError if the tree is not full and balanced."""
    nodes, root = case["nodes"], case["root"]
    levels = [[root]]
    while all(nodes[i]["kind"] == "unified" for i in levels[-1]):
        levels.append([c for i in levels[-1] for c in nodes[i]["children"]])
    if not all(nodes[i]["kind"] == "quadric" for i in levels[-1]):
        raise ValueError("case tree is not a full balanced binary tree")
    return levels[-1], list(reversed(levels[:-1]))


def case_loss_and_grad(case, dtype=torch.float64):
    """Loss, gradient (over the whole parameter vector) and occupancy of a case file."""
    nodes = case["nodes"]
    leaves, inner = case_structure(case)
    theta = torch.tensor(case["params"], dtype=dtype, requires_grad=True)

    def gather(index):
        return theta[torch.tensor(index, dtype=torch.long)]

    def scalar_per_node(layer, key):
        refs = [nodes[i][key] for i in layer]
        if all("param" in r for r in refs):
            return gather([r["param"] for r in refs])
        if all("value" in r for r in refs):
            return torch.tensor([r["value"] for r in refs], dtype=dtype)
        raise ValueError(f"mixed {key} references in one layer")

    Q = gather([nodes[i]["coefficients"] for i in leaves])
    s = gather([nodes[i]["sharpness"] for i in leaves])
    layers = [(gather([nodes[i]["logits"] for i in layer]), scalar_per_node(layer, "temperature"),
               scalar_per_node(layer, "omega")) for layer in inner]
    points = torch.tensor(case["points"], dtype=dtype).view(-1, 3)
    targets = torch.tensor(case["targets"], dtype=dtype)
    occupancy = tree_occupancy(monomials(points), Q, s, layers)
    loss = mse(occupancy, targets)
    loss.backward()
    return loss.item(), theta.grad.tolist(), occupancy.detach().tolist()


def grad_command(args):
    with open(args.case) as f:
        case = json.load(f)
    dtype = torch.float64 if args.dtype == "float64" else torch.float32
    loss, grad, occupancy = case_loss_and_grad(case, dtype)
    text = json.dumps({"impl": "torch", "dtype": args.dtype, "loss": loss, "grad": grad,
                       "occupancy": occupancy})
    if args.out:
        with open(args.out, "w") as f:
            f.write(text + "\n")
    else:
        print(text)


# ---- self-test ---------------------------------------------------------------------------


def _recursive_occupancy(point, Q, s, logits_by_layer, t, omega):
    """The paper's tree evaluated directly by recursion over nodes, in Python floats; a point of
    two coordinates is a 2D point (2D quadrics)."""
    if len(point) == 2:
        x, y = point
        m = (x * x, y * y, x * y, x, y, 1.0)
    else:
        x, y, z = point
        m = (x * x, y * y, z * z, x * y, y * z, z * x, x, y, z, 1.0)

    def node(layer, k):  # layer 0 = leaves
        if layer == 0:
            f = sum(q * mi for q, mi in zip(Q[k], m))
            return 1.0 / (1.0 + math.exp(s[k] * f))
        u = [math.sin(omega * v) * t for v in logits_by_layer[layer - 1][k]]
        mx = max(u)
        e = [math.exp(v - mx) for v in u]
        c = [v / sum(e) for v in e]
        a, b = node(layer - 1, 2 * k), node(layer - 1, 2 * k + 1)
        return (c[1] + c[2]) * a + (c[1] + c[3]) * b + (c[0] - c[1] - c[2] - c[3]) * a * b

    return node(len(logits_by_layer), 0)


def selftest(_args):
    ok = True
    torch.manual_seed(0)
    for dim in (3, 2):
        model = PaperModel(16, seed=3, dtype=torch.float64, dim=dim)
        with torch.no_grad():
            model.s.mul_(20.0)  # sharper leaves: occupancies spread over (0, 1)
            for l in model.logits:
                l.mul_(0.3)  # mixed operators, not one-hot
        points, _ = make_points(64, 5, torch.float64, dim=dim)
        layers = [(l, 2.0, 3.0) for l in model.logits]
        got = tree_occupancy(monomials(points), model.Q, model.s, layers)
        Q, s = model.Q.tolist(), model.s.tolist()
        lg = [l.tolist() for l in model.logits]
        want = torch.tensor([_recursive_occupancy(p, Q, s, lg, 2.0, 3.0)
                             for p in points.tolist()], dtype=torch.float64)
        got_mm = tree_occupancy(monomials(points), model.Q, model.s, layers, "matmul")
        err = max((got - want).abs().max().item(), (got_mm - want).abs().max().item())
        spread = (want.min().item(), want.max().item())
        passed = err < 1e-12
        ok &= passed
        print(f"{dim}D layered (both leaf forms) vs recursive occupancy (P=16, N=64, float64): "
              f"max |diff| = {err:.2e}, occupancy range [{spread[0]:.3f}, {spread[1]:.3f}] "
              f"-> {'ok' if passed else 'FAIL'}")

    small = PaperModel(4, seed=4, dtype=torch.float64)
    pts, tg = make_points(16, 6, torch.float64)

    def f(Q, s, l0, l1):
        return mse(tree_occupancy(monomials(pts), Q, s, [(l0, 2.0, 3.0), (l1, 2.0, 3.0)]), tg)

    passed = torch.autograd.gradcheck(f, tuple(small.parameters()), eps=1e-6, atol=1e-7)
    ok &= passed
    print(f"autograd vs finite differences (P=4, N=16, t=2, omega=3): "
          f"{'ok' if passed else 'FAIL'}")

    m32 = PaperModel(64, seed=1)
    p32, t32 = make_points(4096, 2)
    full, g_full = m32.loss_and_grad(p32, t32, 0)
    part, g_part = m32.loss_and_grad(p32, t32, 1000)
    rel = max(((a - b).abs().max() / a.abs().max().clamp_min(1e-30)).item()
              for a, b in zip(g_full, g_part))
    passed = abs(full.item() - part.item()) <= 1e-6 * abs(full.item()) and rel < 1e-4
    ok &= passed
    print(f"chunked (1000) vs whole batch (P=64, N=4096, float32): loss {full.item():.7g} vs "
          f"{part.item():.7g}, max normwise grad diff {rel:.1e} -> {'ok' if passed else 'FAIL'}")

    # One Adam step of `train` (the release settings of each case): the leaf coefficients and
    # sharpness move, no parameter by more than lr (Adam's first step is lr * g / (|g| + eps);
    # 1e-3 relative slack for the float32 rounding of the parameters), and the loss is finite.
    # Operator logits may not move: at t = 100 or 1000 most softmaxes are one-hot in float32 and
    # their gradient is exactly zero (a property of the model, not of this code).
    for dim, t, lr in ((2, 1000.0, 1e-3), (3, 100.0, 5e-4)):
        tm = PaperModel(16, seed=7, dim=dim)
        opt = torch.optim.Adam(tm.parameters(), lr=lr)
        before = [p.detach().clone() for p in tm.parameters()]
        loss = train_steps(tm, opt, [make_points(512, 8, dim=dim)], 0, 1, 10, temperature=t)
        deltas = [(p.detach() - b).abs() for p, b in zip(tm.parameters(), before)]
        moved = [int((d > 0).sum()) for d in deltas]
        sizes = [d.numel() for d in deltas]
        biggest = max(float(d.max()) for d in deltas)
        passed = (math.isfinite(float(loss)) and moved[0] == sizes[0] and moved[1] == sizes[1]
                  and biggest <= lr * (1 + 1e-3))
        ok &= passed
        print(f"{dim}D Adam train step (P=16, N=512, t={t:g}, lr={lr:g}): loss {float(loss):.5g}; "
              f"moved: coefficients {moved[0]}/{sizes[0]}, sharpness {moved[1]}/{sizes[1]}, "
              f"logits {sum(moved[2:])}/{sum(sizes[2:])}; max |step| {biggest:.4g} "
              f"-> {'ok' if passed else 'FAIL'}")
    return 0 if ok else 1


# ---- command line ------------------------------------------------------------------------


def int_list(text):
    return [int(v) for v in text.split(",") if v]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    sub = ap.add_subparsers(dest="command", required=True)
    b = sub.add_parser("bench", help="time forward+backward")
    b.add_argument("--P", type=int_list, default=[64, 256, 1024])
    b.add_argument("--N", type=int_list, default=[1024, 65536])
    b.add_argument("--threads", type=int_list, default=[1, 2])
    b.add_argument("--reps", type=int, default=5, help="minimum timed repetitions")
    b.add_argument("--min-time", type=float, default=0.2, help="minimum timed seconds")
    b.add_argument("--warmup", type=int, default=1)
    b.add_argument("--chunk", type=int, default=-1,
                   help="points per slice; 0: all at once; -1 (default): about "
                        f"{AUTO_CHUNK_ELEMENTS} leaf-points per slice")
    b.add_argument("--leaf", choices=("elementwise", "matmul"), default="elementwise",
                   help="how the leaf layer computes s f (see leaf_values)")
    b.add_argument("--seed", type=int, default=1)
    g = sub.add_parser("grad", help="loss and gradient of a case file")
    g.add_argument("case")
    g.add_argument("--dtype", choices=("float32", "float64"), default="float64")
    g.add_argument("--out", help="write here instead of stdout")
    tr = sub.add_parser("train", help="time Adam training steps (the authors' release)")
    tr.add_argument("--dim", type=int, choices=(2, 3), default=3)
    tr.add_argument("--P", type=int, default=1024, help="leaves (a power of two)")
    tr.add_argument("--batch", type=int, default=1024, help="points per step")
    tr.add_argument("--steps", type=int, default=200, help="timed steps per repetition")
    tr.add_argument("--reps", type=int, default=3, help="timed repetitions (median reported)")
    tr.add_argument("--warmup", type=int, default=10, help="untimed steps first")
    tr.add_argument("--threads", type=int, default=2)
    tr.add_argument("--temperature", type=float, default=TEMPERATURE)
    tr.add_argument("--omega", type=float, default=OMEGA)
    tr.add_argument("--lr", type=float, default=1e-3, help="Adam learning rate")
    tr.add_argument("--resample-every", type=int, default=10,
                    help="steps between fresh point batches")
    tr.add_argument("--batches", type=int, default=8,
                    help="point batches generated before timing and cycled through")
    tr.add_argument("--chunk", type=int, default=-1,
                    help="points per slice; 0: all at once; -1 (default): as `bench`")
    tr.add_argument("--leaf", choices=("elementwise", "matmul"), default="elementwise")
    tr.add_argument("--seed", type=int, default=0)
    sub.add_parser("selftest", help="check the model against a direct evaluation")
    args = ap.parse_args(argv)
    if args.command == "bench":
        bench(args)
        return 0
    if args.command == "train":
        train(args)
        return 0
    if args.command == "grad":
        grad_command(args)
        return 0
    return selftest(args)


if __name__ == "__main__":
    sys.exit(main())
