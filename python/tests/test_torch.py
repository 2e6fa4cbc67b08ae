"""fuzzycsg.torch: the C++ layer against the pure-PyTorch model (values, and gradients by
gradcheck and by autograd of the reference), batches turned into trees, and bad input."""

import numpy as np
import pytest
import torch

import fuzzycsg
from fuzzycsg import reference
from fuzzycsg.torch import CSGLayer


def batch(layer, b=3, n=200, seed=0, dtype=torch.float64, scale=0.6):
    g = torch.Generator().manual_seed(seed)
    leaf = (torch.rand(b, layer.leaves, layer.leaf_size, generator=g, dtype=dtype) - 0.5) * scale
    if layer.family in ("sphere", "circle"):
        leaf[..., 0] = leaf[..., 0].abs() + 0.2
    logits = (torch.rand(b, layer.leaves - 1, 4, generator=g, dtype=dtype) - 0.5)
    temperature = torch.full((b,), 3.0, dtype=dtype)
    points = (torch.rand(b, n, layer.dim, generator=g, dtype=dtype) * 2 - 1)
    return leaf, logits, temperature, points


@pytest.mark.parametrize("dim,family,leaves", [(3, "quadric", 8), (2, "quadric", 4),
                                               (3, "sphere", 4), (2, "circle", 8)])
def test_forward_and_backward_match_the_reference(dim, family, leaves):
    layer = CSGLayer(leaves, dim=dim, family=family, sharpness=4.0)
    ref = CSGLayer(leaves, dim=dim, family=family, sharpness=4.0, backend="torch")
    inputs = [t.requires_grad_() for t in batch(layer)]
    out = layer(*inputs)
    inputs_ref = [t.detach().clone().requires_grad_() for t in inputs]
    out_ref = ref(*inputs_ref)
    assert out.shape == (3, 200) and out.dtype == torch.float64
    torch.testing.assert_close(out, out_ref, atol=2e-6, rtol=0)
    w = torch.randn(3, 200, dtype=torch.float64, generator=torch.Generator().manual_seed(1))
    grads = torch.autograd.grad((out * w).sum(), inputs)
    grads_ref = torch.autograd.grad((out_ref * w).sum(), inputs_ref)
    for name, g, gr in zip(("leaf", "logits", "temperature", "points"), grads, grads_ref):
        scale = gr.abs().max().item()
        torch.testing.assert_close(g, gr, atol=2e-4 * max(scale, 1.0), rtol=1e-3, msg=name)


def test_gradcheck():
    layer = CSGLayer(4, dim=3, family="quadric", sharpness=2.0)
    ref = CSGLayer(4, dim=3, family="quadric", sharpness=2.0, backend="torch")
    inputs = tuple(t.requires_grad_() for t in batch(layer, b=2, n=12, seed=3))
    # The specification in float64 (pure PyTorch) ...
    assert torch.autograd.gradcheck(ref, inputs)
    # ... and the kernel, whose arithmetic is float32: its Jacobians against differences.
    assert torch.autograd.gradcheck(layer, inputs, eps=1e-3, atol=2e-3, rtol=2e-2)


def test_product_operators_and_their_baseline():
    layer = CSGLayer(8, ops="product", seed=4, sharpness=3.0)
    ref = CSGLayer(8, ops="product", seed=4, sharpness=3.0, backend="torch")
    assert not layer.unified and set(layer.operator_types) <= {"union", "intersection",
                                                                 "difference"}
    leaf, _, _, points = batch(layer)
    leaf.requires_grad_()
    out, out_ref = layer(leaf, points=points), ref(leaf.detach().requires_grad_(), points=points)
    torch.testing.assert_close(out, out_ref, atol=2e-6, rtol=0)
    (g,) = torch.autograd.grad(out.sum(), leaf)
    assert torch.isfinite(g).all() and g.abs().sum() > 0


def test_a_batch_member_is_an_ordinary_tree(tmp_path):
    layer = CSGLayer(8, sharpness=4.0)
    leaf, logits, temperature, points = batch(layer, dtype=torch.float32)
    out = layer(leaf, logits, temperature, points)
    tree = layer.tree(leaf, logits, temperature=3.0, index=1)
    occ = fuzzycsg.eval(tree, points[1].numpy())
    np.testing.assert_allclose(occ, out[1].numpy(), atol=1e-6)
    tree.write(str(tmp_path / "decoded.json"))
    pruned, report = fuzzycsg.prune(fuzzycsg.Tree.read(str(tmp_path / "decoded.json")))
    assert report["primitives_after"] <= 8


def test_same_results_for_any_thread_count():
    one, two = CSGLayer(16, threads=1), CSGLayer(16, threads=2)
    inputs = batch(one, b=2, n=5000, dtype=torch.float32)
    a = [t.clone().requires_grad_() for t in inputs]
    b = [t.clone().requires_grad_() for t in inputs]
    oa, ob = one(*a), two(*b)
    assert torch.equal(oa, ob)
    for ga, gb in zip(torch.autograd.grad(oa.sum(), a), torch.autograd.grad(ob.sum(), b)):
        assert torch.equal(ga, gb)


def test_bad_input():
    layer = CSGLayer(4)
    leaf, logits, temperature, points = batch(layer, b=2, n=10, dtype=torch.float32)
    with pytest.raises(ValueError, match=r"leaf: shape \(2, 4, 9\), expected \(\*, 4, 10\)"):
        layer(leaf[..., :9], logits, temperature, points)
    with pytest.raises(ValueError, match=r"logits: shape"):
        layer(leaf, logits[:, :2], temperature, points)
    with pytest.raises(ValueError, match=r"points: shape"):
        layer(leaf, logits, temperature, points[..., :2])
    with pytest.raises(TypeError, match="points: dtype torch.int64"):
        layer(leaf, logits, temperature, points.long())
    with pytest.raises(TypeError, match="different dtypes"):
        layer(leaf.double(), logits, temperature, points)
    with pytest.raises(ValueError, match="different devices"):
        layer(leaf, logits, temperature, points.to("meta"))
    bad = leaf.clone()
    bad[1, 2, 3] = float("inf")
    with pytest.raises(ValueError, match="leaf: entry .* is not finite"):
        layer(bad, logits, temperature, points)
    with pytest.raises(ValueError, match="temperature: must be > 0"):
        layer(leaf, logits, torch.zeros(2), points)
    with pytest.raises(TypeError, match="a torch.Tensor expected"):
        layer(leaf.numpy(), logits, temperature, points)
    with pytest.raises(fuzzycsg.OptionError, match="^leaves: must be a power of two"):
        CSGLayer(6)
    with pytest.raises(fuzzycsg.OptionError, match="^family: unknown 3D primitive"):
        CSGLayer(4, family="blob")
    with pytest.raises(ValueError, match="leaves"):
        reference.level_order(6)


def test_level_order_is_post_order():
    # Leaves 0..3: the operators in post-order are (0 1), (2 3), root.
    assert reference.level_order(4) == ((0, 1), (2,))
    assert reference.level_order(8) == ((0, 1, 3, 4), (2, 5), (6,))
