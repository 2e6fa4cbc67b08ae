"""A differentiable CSG layer for PyTorch over fuzzycsg's C++ kernel.

``CSGLayer(leaves, dim, family)`` evaluates a batch of B full binary trees of one topology: the
leaves' parameters (B x P x k, k = ``layer.leaf_size``, fields ``layer.leaf_fields``), the
unified operators' logits (B x (P-1) x 4, post-order), a temperature (B, or one number) and
the query points (B x N x dim) give the occupancy (B x N). The backward pass is the kernel's
reverse sweep: gradients reach every input, the points included. ``layer.tree(...)`` turns one
member of a batch into an ordinary ``fuzzycsg.Tree`` (prune, mesh, export it).

The kernel runs on the CPU in float32 (its results are the same for any thread count); tensors
on another device are copied there and the results copied back. ``backend="torch"`` evaluates
the same model in pure PyTorch instead (``fuzzycsg.reference``), on the tensors' own device.

    layer = CSGLayer(leaves=512, family="quadric")
    occ = layer(leaf, logits, temperature, points)     # B x N
"""

from __future__ import annotations

import torch

from . import _fuzzycsg
from . import reference as _reference

_FLOATS = (torch.float32, torch.float64)


def _check(leaf, logits, temperature, points, unified: bool):
    tensors = {"leaf": leaf, "points": points}
    if unified:
        tensors.update(logits=logits, temperature=temperature)
    for name, t in tensors.items():
        if not isinstance(t, torch.Tensor):
            raise TypeError(f"{name}: a torch.Tensor expected, got {type(t).__name__}")
        if t.dtype not in _FLOATS:
            raise TypeError(f"{name}: dtype {t.dtype}, expected torch.float32 or torch.float64")
    devices = {t.device for t in tensors.values()}
    if len(devices) > 1:
        raise ValueError(f"the inputs are on different devices: {sorted(map(str, devices))}")
    dtypes = {t.dtype for t in tensors.values()}
    if len(dtypes) > 1:
        raise TypeError(f"the inputs have different dtypes: {sorted(map(str, dtypes))}")


def _numpy(t: torch.Tensor, dtype) -> "numpy.ndarray":  # noqa: F821
    return t.detach().to(device="cpu", dtype=dtype).contiguous().numpy()


class TreeFunction(torch.autograd.Function):
    """occupancy = f(leaf, logits, temperature, points) through the C++ kernel."""

    @staticmethod
    def forward(ctx, layer, leaf, logits, temperature, points):
        ctx.layer = layer
        ctx.save_for_backward(leaf, logits, temperature, points)
        occ = layer.forward(_numpy(leaf, torch.float64), _numpy(logits, torch.float64),
                            _numpy(temperature, torch.float64), _numpy(points, torch.float32))
        return torch.from_numpy(occ).to(device=leaf.device, dtype=leaf.dtype)

    @staticmethod
    @torch.autograd.function.once_differentiable
    def backward(ctx, grad_output):
        leaf, logits, temperature, points = ctx.saved_tensors
        need = ctx.needs_input_grad
        d_leaf, d_logits, d_temp, d_points = ctx.layer.backward(
            _numpy(leaf, torch.float64), _numpy(logits, torch.float64),
            _numpy(temperature, torch.float64), _numpy(points, torch.float32),
            _numpy(grad_output, torch.float32), points_grad=bool(need[4]))

        def back(a, like, needed):
            if not needed or a is None:
                return None
            return torch.from_numpy(a).to(device=like.device, dtype=like.dtype)

        return (None, back(d_leaf, leaf, need[1]), back(d_logits, logits, need[2]),
                back(d_temp, temperature, need[3]), back(d_points, points, need[4]))


class CSGLayer(torch.nn.Module):
    """Occupancy of a batch of full binary trees of ``leaves`` leaves of one family (``quadric``
    by default; any family of the tree format) with unified operators (``ops="unified"``) or
    fixed booleans of product logic drawn with ``seed`` (``ops="product"``)."""

    def __init__(self, leaves: int, dim: int = 3, family: str = "quadric", ops: str = "unified",
                 sharpness: float | None = None, omega: float = 10.0, seed: int = 0,
                 threads: int = 0, backend: str = "kernel"):
        super().__init__()
        if backend not in ("kernel", "torch"):
            raise ValueError(f"backend: 'kernel' or 'torch', not {backend!r}")
        self.kernel = _fuzzycsg.TreeLayer(leaves, dim, family, ops, sharpness, omega, seed,
                                          threads)
        self.family = family
        self.omega = omega
        self.backend = backend
        self.sharpness = self.kernel.sharpness

    @property
    def leaves(self) -> int:
        return self.kernel.leaves

    @property
    def dim(self) -> int:
        return self.kernel.dim

    @property
    def leaf_size(self) -> int:
        return self.kernel.leaf_size

    @property
    def leaf_fields(self) -> list:
        return self.kernel.leaf_fields

    @property
    def unified(self) -> bool:
        return self.kernel.unified

    @property
    def operator_types(self) -> list:
        return self.kernel.operator_types

    def forward(self, leaf, logits=None, temperature=1000.0, points=None):
        if points is None:
            raise TypeError("forward(): points missing")
        if self.unified:
            if logits is None:
                raise TypeError("forward(): logits missing (unified operators)")
            if not isinstance(temperature, torch.Tensor):
                temperature = torch.full((leaf.shape[0],), float(temperature), dtype=leaf.dtype,
                                         device=leaf.device)
        _check(leaf, logits, temperature, points, self.unified)
        if self.backend == "torch":
            return _reference.occupancy(
                leaf, logits if self.unified else None, temperature, points, family=self.family,
                sharpness=self.sharpness, omega=self.omega, operator_types=self.operator_types)
        if not self.unified:
            logits = leaf.new_zeros(leaf.shape[0], 0, 4)
            temperature = leaf.new_ones(leaf.shape[0])
        return TreeFunction.apply(self.kernel, leaf, logits, temperature, points)

    def tree(self, leaf, logits=None, temperature: float = 1000.0, index: int = 0):
        """Member ``index`` of a batch as a ``fuzzycsg.Tree`` (unified operators at
        ``temperature``; snap and prune it with ``fuzzycsg.prune``)."""
        l = _numpy(leaf[index], torch.float64)
        c = None if logits is None or not self.unified else _numpy(logits[index], torch.float64)
        if self.unified and c is None:
            raise TypeError("tree(): logits missing (unified operators)")
        return self.kernel.tree(l, c, float(temperature))
