"""The procedural data set (reproducible, labels that are the tree's) and the generative model
(trains, measures, decodes to ordinary trees), on a tiny configuration."""

import json
import os
import subprocess

import numpy as np
import pytest
import torch

import fuzzycsg
from fuzzycsg import dataset, generative


@pytest.fixture(scope="module")
def data(tmp_path_factory):
    root = tmp_path_factory.mktemp("csg")
    dataset.main(["-o", str(root), "--train", "12", "--test", "4", "--seed", "3"])
    return root


def test_the_same_seed_makes_the_same_shapes():
    a = dataset.make_split(3, [5, 0], cloud=64, samples=256, eval_samples=512)
    b = dataset.make_split(3, [5, 0], cloud=64, samples=256, eval_samples=512)
    c = dataset.make_split(3, [6, 0], cloud=64, samples=256, eval_samples=512)
    assert a["trees"] == b["trees"] and a["trees"] != c["trees"]
    for key in ("cloud", "points", "occupancy", "eval_points", "eval_occupancy"):
        np.testing.assert_array_equal(a[key], b[key])


def test_shapes_are_their_trees(data):
    split = dataset.load(str(data / "test.npz"))
    assert split["cloud"].shape == (4, 1024, 3) and split["points"].shape == (4, 4096, 3)
    for k, text in enumerate(split["trees"]):
        tree = fuzzycsg.Tree.from_json(text)
        families = set(tree.info()["families"])
        assert families <= set(dataset.FAMILIES), families
        inside = fuzzycsg.eval(tree, split["eval_points"][k]) >= 0.5
        np.testing.assert_array_equal(inside, split["eval_occupancy"][k].astype(bool))
        assert 0.03 <= inside.mean() <= 0.5
        # The cloud lies on the surface: the occupancy there is about one half.
        occ = fuzzycsg.eval(tree, split["cloud"][k])
        assert np.median(np.abs(occ - 0.5)) < 0.3


TINY = dict(leaves=8, latent=32, batch=4, points=256, cloud=128, steps=40, lr=3e-3, threads=2)


@pytest.mark.parametrize("decoder", ["unified", "product"])
def test_training_evaluation_and_decoded_trees(data, tmp_path, decoder):
    run = tmp_path / decoder
    log = generative.train(str(data), str(run), decoder=decoder, **TINY)
    assert log["steps"] == 40 and len(log["curve"]) == 10
    first, last = log["curve"][0][1], log["curve"][-1][1]
    assert np.isfinite(last) and last < first, (first, last)
    # The same seed trains the same model.
    again = generative.train(str(data), str(tmp_path / "again"), decoder=decoder, **TINY)
    without_time = lambda curve: [(r[0], r[1], r[3]) for r in curve]  # noqa: E731
    assert without_time(again["curve"]) == without_time(log["curve"])
    result = generative.evaluate(str(data), str(run))
    assert json.loads((run / "evaluation.json").read_text()) == result
    for key in ("fuzzy", "pruned"):
        m = result[key]
        assert 0 <= m["mse"] <= 1 and 0 <= m["accuracy"] <= 1 and 0 <= m["fscore"] <= 1
    assert result["nodes_before"] == [8, 7]
    assert result["nodes_after_max"][0] <= 8
    # A decoded shape is an ordinary tree.
    model = generative.load_model(str(run))
    split = dataset.load(str(data / "test.npz"))
    z = model.encoder(torch.from_numpy(split["cloud"][:2, :128]))
    trees = model.trees(z, generative.temperature_at(model.config, 1.0))
    path = tmp_path / "decoded.json"
    trees[1].write(str(path))
    occ = model.decoder(z, torch.from_numpy(split["eval_points"][:2]),
                        generative.temperature_at(model.config, 1.0))
    np.testing.assert_allclose(fuzzycsg.eval(fuzzycsg.Tree.read(str(path)),
                                             split["eval_points"][1]),
                               occ[1].detach().numpy(), atol=1e-5)
    pruned, _ = fuzzycsg.prune(trees[1], split["eval_points"][1])
    assert fuzzycsg.export_report(pruned)["leaves"] == pruned.info()["primitives"]
    # ... which the program's verbs read.
    program = os.environ["FUZZYCSG_PROGRAM"]
    for verb, out in (("prune", "pruned.json"), ("export", "model.scad")):
        args = [program, verb, str(path), "-o", str(tmp_path / out)]
        if verb == "prune":
            args += ["--target", str(path), "--no-metrics", "--points", "4096"]
        r = subprocess.run(args, capture_output=True, text=True)
        assert r.returncode == 0 and (tmp_path / out).stat().st_size > 0, r.stderr


def test_pictures_of_reconstructions_and_an_interpolation(data, tmp_path):
    import matplotlib.image as mpimg

    runs = []
    for decoder in ("unified", "product"):
        run = tmp_path / decoder
        generative.train(str(data), str(run), decoder=decoder, **{**TINY, "steps": 4})
        runs.append(str(run))
    written = generative.pictures(str(data), runs, str(tmp_path / "pics"), shapes=(0, 1),
                                  interpolate=(0, 1), frames=3)
    grid = mpimg.imread(written[0])
    strip = mpimg.imread(written[1])
    # Three rows (inputs, two decoders) of two pictures; one row of three frames.
    assert grid.shape[0] > strip.shape[0] and grid.shape[1] < strip.shape[1]
    assert grid[..., :3].std() > 0.05  # not blank
