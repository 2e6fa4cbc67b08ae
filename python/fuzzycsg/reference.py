"""A pure-PyTorch implementation of the trees ``fuzzycsg.torch.CSGLayer`` evaluates: the full
binary tree of P leaves of Liu et al. 2024, every leaf a quadric (or a ball) with a sigmoid step,
every operator the unified operator B_c with c = softmax(sin(omega * logits) * t) (eq. 21) or a
fixed boolean of product logic.

It is the layer's reference (tests check the C++ kernel against it, values and gradients) and
its baseline in bench/, and it runs wherever PyTorch does (CUDA included).

Conventions, as the C++ library's (core/primitives.hpp, core/logic.hpp):
- quadric (3D): f = q . (x², y², z², xy, yz, zx, x, y, z, 1); quadric (2D): q . (x², y², xy,
  x, y, 1); sphere / circle: f = |p - t| - r with parameters (r, t). Occupancy
  o = 1 / (1 + exp(s f)): inside where f < 0.
- B_c(x, y) = c0 xy + c1 (x + y - xy) + c2 x (1 - y) + c3 y (1 - x): intersection, union,
  x minus y, y minus x.
- Operators are numbered in post-order (the tree file's node order), leaves left to right.
"""

from __future__ import annotations

import math
from functools import lru_cache

import torch


@lru_cache(maxsize=None)
def level_order(leaves: int) -> tuple:
    """For each level of the full binary tree of ``leaves`` leaves, bottom up, the post-order
    numbers of its operators, left to right."""
    if leaves < 2 or leaves & (leaves - 1):
        raise ValueError(f"leaves: must be a power of two >= 2, got {leaves}")
    depth = int(math.log2(leaves))
    levels = [[0] * (leaves >> (d + 1)) for d in range(depth)]
    counter = 0

    def visit(lo: int, hi: int) -> None:
        nonlocal counter
        if hi - lo == 1:
            return
        mid = (lo + hi) // 2
        visit(lo, mid)
        visit(mid, hi)
        width = hi - lo
        levels[int(math.log2(width)) - 1][lo // width] = counter
        counter += 1

    visit(0, leaves)
    return tuple(tuple(level) for level in levels)


def leaf_values(leaf: torch.Tensor, points: torch.Tensor, family: str) -> torch.Tensor:
    """The leaves' implicit functions f (B x P x N) at the points (B x N x dim)."""
    dim = points.shape[-1]
    if family == "quadric":
        x, y = points[..., 0], points[..., 1]
        one = torch.ones_like(x)
        if dim == 3:
            z = points[..., 2]
            mono = torch.stack([x * x, y * y, z * z, x * y, y * z, z * x, x, y, z, one], -1)
        else:
            mono = torch.stack([x * x, y * y, x * y, x, y, one], -1)
        return torch.einsum("bnk,bpk->bpn", mono, leaf)
    if family in ("sphere", "circle"):
        r, t = leaf[..., 0], leaf[..., 1:]
        d = points[:, None, :, :] - t[:, :, None, :]
        return torch.sqrt((d * d).sum(-1)) - r[..., None]
    raise ValueError(f"family: the reference has quadric, sphere and circle, not {family}")


def combine(x: torch.Tensor, y: torch.Tensor, c: torch.Tensor) -> torch.Tensor:
    """B_c(x, y) with weights c (..., 4) broadcast over the points."""
    xy = x * y
    c0, c1, c2, c3 = (c[..., k, None] for k in range(4))
    return c0 * xy + c1 * (x + y - xy) + c2 * (x - xy) + c3 * (y - xy)


_PRODUCT = {
    "intersection": (1.0, 0.0, 0.0, 0.0),
    "union": (0.0, 1.0, 0.0, 0.0),
    "difference": (0.0, 0.0, 1.0, 0.0),
}


def occupancy(leaf: torch.Tensor, logits, temperature, points: torch.Tensor, *,
              family: str = "quadric", sharpness: float = 1.0, omega: float = 10.0,
              operator_types=None) -> torch.Tensor:
    """Occupancy (B x N) of B full binary trees. ``leaf``: B x P x k; ``logits``: B x (P-1) x 4
    (unified operators), or None with ``operator_types`` (post-order names: union, intersection,
    difference) for fixed booleans of product logic; ``temperature``: B (or a number)."""
    values = torch.sigmoid(-sharpness * leaf_values(leaf, points, family))
    b, p = leaf.shape[0], leaf.shape[1]
    if logits is not None:
        t = torch.as_tensor(temperature, dtype=leaf.dtype, device=leaf.device)
        t = t.reshape(-1, 1, 1) if t.dim() > 0 else t
        weights = torch.softmax(torch.sin(omega * logits) * t, dim=-1)
    else:
        table = torch.tensor([_PRODUCT[name] for name in operator_types], dtype=leaf.dtype,
                             device=leaf.device)
        weights = table.expand(b, p - 1, 4)
    for level in level_order(p):
        idx = torch.tensor(level, device=leaf.device)
        values = combine(values[:, 0::2], values[:, 1::2], weights[:, idx])
    return values[:, 0]
