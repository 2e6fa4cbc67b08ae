"""fuzzycsg.Tree, eval and grad: values against the formulas, gradients against differences,
bad input as exceptions with the program's messages."""

import math
import threading
import time

import numpy as np
import pytest

import fuzzycsg

SPHERE = """{"format": "fuzzycsg-tree", "version": 1, "dim": 3,
  "root": {"type": "sphere", "radius": 0.5, "translate": [0.1, -0.2, 0.3], "sharpness": 8}}"""


def sphere_occupancy(points, r=0.5, c=(0.1, -0.2, 0.3), s=8.0):
    d = np.linalg.norm(points - np.asarray(c), axis=1) - r
    return 1.0 / (1.0 + np.exp(s * d))


def test_read_write_and_parameters(tmp_path, source):
    tree = fuzzycsg.Tree.read(str(source / "examples" / "box_with_hole.json"))
    assert tree.dim == 3 and tree.num_params == len(tree.names) == tree.values.shape[0]
    info = tree.info()
    assert info["primitives"] == 2 and info["operators"] == 1, info
    params = tree.parameters()
    assert sum(v.size for v in params.values()) == tree.num_params
    size = [n for n in params if n.endswith(".size")][0]
    assert params[size].shape == (3,)
    tree.set(size, [1.5, 1.25, 1.0])
    np.testing.assert_array_equal(tree.get(size), [1.5, 1.25, 1.0])
    path = tmp_path / "t.json"
    tree.write(str(path))
    again = fuzzycsg.Tree.read(str(path))
    np.testing.assert_array_equal(again.values, tree.values)
    assert fuzzycsg.Tree.from_json(tree.to_json()).names == tree.names
    with pytest.raises(KeyError):
        tree.get("root.nothing")
    # A value out of its field's range is refused and the tree is unchanged.
    with pytest.raises(fuzzycsg.InputError, match="size"):
        tree.set(size, [-1.0, 1.0, 1.0])
    np.testing.assert_array_equal(tree.get(size), [1.5, 1.25, 1.0])


def test_eval_matches_the_formula_for_any_layout():
    tree = fuzzycsg.Tree.from_json(SPHERE)
    rng = np.random.default_rng(1)
    pts = rng.uniform(-1, 1, (1000, 3))
    expected = sphere_occupancy(pts)
    for given in (pts.astype(np.float32), pts, np.asfortranarray(pts), pts.tolist()):
        occ = fuzzycsg.eval(tree, given)
        assert occ.dtype == np.float32 and occ.shape == (1000,)
        np.testing.assert_allclose(occ, expected, atol=2e-6)
    # Other parameters than the tree's own.
    values = tree.values.copy()
    values[tree.names.index("root.radius")] = 0.25
    np.testing.assert_allclose(fuzzycsg.eval(tree, pts, params=values),
                               sphere_occupancy(pts, r=0.25), atol=2e-6)


def test_grad_by_parameters_and_points_against_differences():
    tree = fuzzycsg.full_binary_tree(leaves=8, seed=3, temperature=3.0)
    rng = np.random.default_rng(2)
    pts = rng.uniform(-1, 1, (300, 3)).astype(np.float32)
    w = rng.uniform(-1, 1, 300).astype(np.float32)
    loss, g, pg = fuzzycsg.grad(tree, pts, w, points_grad=True)
    values = tree.values
    assert g.shape == values.shape and pg.shape == pts.shape
    assert loss == pytest.approx(float(np.dot(w, fuzzycsg.eval(tree, pts))), rel=1e-5)
    h = 1e-2
    for k in rng.choice(np.flatnonzero(~tree.fixed), 12, replace=False):
        plus, minus = values.copy(), values.copy()
        plus[k] += h
        minus[k] -= h
        fd = (np.dot(w, fuzzycsg.eval(tree, pts, params=plus)) -
              np.dot(w, fuzzycsg.eval(tree, pts, params=minus))) / (2 * h)
        assert g[k] == pytest.approx(fd, rel=2e-2, abs=2e-2), tree.names[k]
    for i in range(0, 300, 37):
        for j in range(3):
            p, m = pts.copy(), pts.copy()
            p[i, j] += h
            m[i, j] -= h
            fd = w[i] * (fuzzycsg.eval(tree, p[i:i + 1])[0] - fuzzycsg.eval(tree, m[i:i + 1])[0]) / (2 * h)
            assert pg[i, j] == pytest.approx(fd, rel=2e-2, abs=1e-3), (i, j)
    # The mean squared error.
    targets = (rng.uniform(size=300) > 0.5).astype(np.float32)
    mse, gm = fuzzycsg.grad(tree, pts, loss="mse", targets=targets)
    occ = fuzzycsg.eval(tree, pts)
    assert mse == pytest.approx(float(np.mean((occ - targets) ** 2)), rel=1e-5)
    _, gs = fuzzycsg.grad(tree, pts, 2.0 * (occ - targets) / 300)
    np.testing.assert_allclose(gm, gs, rtol=1e-4, atol=1e-7)


def test_results_do_not_depend_on_threads():
    tree = fuzzycsg.full_binary_tree(leaves=32, seed=5, temperature=4.0)
    pts = np.random.default_rng(3).uniform(-1, 1, (5000, 3)).astype(np.float32)
    w = np.ones(5000, np.float32)
    one = fuzzycsg.grad(tree, pts, w, threads=1, points_grad=True)
    two = fuzzycsg.grad(tree, pts, w, threads=2, points_grad=True)
    assert one[0] == two[0]
    np.testing.assert_array_equal(one[1], two[1])
    np.testing.assert_array_equal(one[2], two[2])


def test_bad_input_raises_clear_exceptions(tmp_path, program_error):
    tree = fuzzycsg.Tree.from_json(SPHERE)
    with pytest.raises(ValueError, match=r"points: shape \(10, 2\), expected \(\*, 3\)"):
        fuzzycsg.eval(tree, np.zeros((10, 2)))
    bad = np.zeros((4, 3))
    bad[2, 1] = math.nan
    with pytest.raises(ValueError, match="points: entry 7 is not finite"):
        fuzzycsg.eval(tree, bad)
    with pytest.raises(TypeError, match="numeric array"):
        fuzzycsg.eval(tree, np.array([["a", "b", "c"]]))
    with pytest.raises(ValueError, match="params: shape"):
        fuzzycsg.eval(tree, np.zeros((1, 3)), params=np.zeros(2))
    with pytest.raises(ValueError, match="weights: shape"):
        fuzzycsg.grad(tree, np.zeros((3, 3)), np.zeros(4))
    with pytest.raises(fuzzycsg.OptionError, match="^leaves: must be a power of two"):
        fuzzycsg.full_binary_tree(leaves=3)
    # A broken tree file: the same one line as the program.
    broken = tmp_path / "broken.json"
    broken.write_text('{"format": "fuzzycsg-tree", "version": 1, "dim": 3, '
                      '"root": {"type": "sphere", "radius": -1}}')
    with pytest.raises(fuzzycsg.InputError) as e:
        fuzzycsg.Tree.read(str(broken))
    assert str(e.value) == program_error("info", broken)


def test_the_kernel_runs_without_the_gil():
    tree = fuzzycsg.full_binary_tree(leaves=256, seed=1)
    pts = np.random.default_rng(4).uniform(-1, 1, (400_000, 3)).astype(np.float32)
    started = time.perf_counter()
    fuzzycsg.eval(tree, pts, threads=1)
    alone = time.perf_counter() - started
    done = threading.Event()
    worker = threading.Thread(target=lambda: (fuzzycsg.eval(tree, pts, threads=1), done.set()))
    stamps = []
    worker.start()
    while not done.is_set():
        stamps.append(time.perf_counter())
    worker.join()
    gaps = np.diff(stamps) if len(stamps) > 1 else np.array([alone])
    # Holding the GIL would stop this loop for the whole evaluation.
    assert gaps.max() < 0.5 * alone, (gaps.max(), alone)
