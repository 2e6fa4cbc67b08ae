"""The engines from Python: options as keyword arguments, results as objects, the same results
and the same error messages as the program."""

import json

import numpy as np
import pytest

import fuzzycsg

DISC = """{"format": "fuzzycsg-tree", "version": 1, "dim": 2,
  "root": {"type": "circle", "radius": 0.5, "translate": [0.1, 0.0]}}"""

PROGRAM = """{"format": "fuzzycsg-tree", "version": 1, "dim": 3, "root": {"op": "difference",
  "children": [{"type": "box", "size": [1.2, 1, 0.8], "rotate": [0, 0, 10]},
  {"type": "cylinder", "radius": 0.25, "height": 1.2, "translate": [0.1, 0.05, 0],
   "rotate": [20, 0, 0]}]}}"""


def test_fit_to_a_tree_and_its_options():
    disc = fuzzycsg.Tree.from_json(DISC)
    r = fuzzycsg.fit(disc, prims=4, iters=300, batch=512, seed=1, threads=2, lr=0.02,
                     metrics={"points": 20000, "chamfer": False}, sampling={"surface": 0.5})
    assert isinstance(r.pruned, fuzzycsg.Tree) and r.pruned.dim == 2
    assert r.stop == "iterations" and r.steps == 300
    assert r.loss_curve.shape[1] == 3 and r.loss_curve[-1, 1] < r.loss_curve[0, 1]
    assert r.metrics_pruned["iou"] > 0.8, r.metrics_pruned
    # The same fit twice is the same fit.
    again = fuzzycsg.fit(disc, prims=4, iters=300, batch=512, seed=1, threads=2, lr=0.02,
                         metrics={"points": 20000, "chamfer": False}, sampling={"surface": 0.5})
    np.testing.assert_array_equal(again.trained.values, r.trained.values)
    with pytest.raises(TypeError, match="unexpected option 'primz'"):
        fuzzycsg.fit(disc, primz=4)
    with pytest.raises(TypeError, match="sampling.nearby"):
        fuzzycsg.fit(disc, sampling={"nearby": 0.1})
    with pytest.raises(fuzzycsg.OptionError, match="^prims: must be a power of two"):
        fuzzycsg.fit(disc, prims=6)
    with pytest.raises(fuzzycsg.OptionError, match="^ops: unknown value 'fuzzy'"):
        fuzzycsg.fit(disc, ops="fuzzy")
    assert fuzzycsg.options(fuzzycsg.FitOptions)["prims"] == 64


def test_prune_mesh_and_export():
    tree = fuzzycsg.Tree.from_json(PROGRAM)
    pruned, report = fuzzycsg.prune(tree, threshold=1e-3, threads=2)
    assert report["primitives_before"] == 2 and report["primitives_after"] == 2
    vertices, triangles = fuzzycsg.mesh(tree, resolution=32, threads=2)
    assert vertices.shape[1] == 3 and triangles.shape[1] == 3 and len(triangles) > 100
    assert triangles.max() < len(vertices) and triangles.dtype == np.int32
    # The vertices lie on the 0.5 level set (to the linear interpolation across a cell).
    off = np.abs(fuzzycsg.eval(tree, vertices) - 0.5)
    assert np.median(off) < 0.01 and off.max() < 0.3, (np.median(off), off.max())
    scad = fuzzycsg.export(tree)
    assert "difference()" in scad and "cube(" in scad and "cylinder(" in scad
    report = fuzzycsg.export_report(tree)
    assert report["leaves"] == 2
    loops = fuzzycsg.mesh(fuzzycsg.Tree.from_json(DISC), resolution=64)
    assert len(loops) == 1 and loops[0].shape[1] == 2
    r = np.linalg.norm(loops[0] - np.array([0.1, 0.0]), axis=1)
    assert abs(r.mean() - 0.5) < 0.02


def test_mesh_written_to_a_file(tmp_path):
    tree = fuzzycsg.Tree.from_json(PROGRAM)
    path = tmp_path / "m.obj"
    fuzzycsg.mesh(tree, path, resolution=24)
    assert path.read_text().count("\nf ") > 100
    with pytest.raises(fuzzycsg.InputError, match="m.xyz"):
        fuzzycsg.mesh(tree, tmp_path / "m.xyz", resolution=24)


def test_convert_as_the_program_does(source):
    csg = source / "tests" / "data" / "scad" / "Old" / "example004.openscad.csg"
    r = fuzzycsg.convert(csg, threads=2, time_limit=60)
    assert r.primitives == 2 and r.metrics["iou"] > 0.99 and r.reached
    assert "difference()" in r.scad and "written by fuzzycsg convert" in r.scad
    assert r.report["primitives"] == 2
    assert fuzzycsg.eval(r.tree, np.zeros((1, 3)))[0] in (0.0, 1.0)  # crisp


def test_trace_a_glyph(source):
    glyph = source / "tests" / "data" / "glyphs" / "DejaVuSans-Bold_U002B_plus.png"
    r = fuzzycsg.trace(glyph, max_trees=400, population=100, patience=200, seed=2, threads=2)
    assert r.tree.dim == 2 and r.score["primitives"] >= 1
    assert r.score["excess"] + r.score["uncovered"] < 0.1 * r.width * r.height
    refined = fuzzycsg.trace(glyph, max_trees=400, population=100, patience=200, seed=2,
                             threads=2, refine=True, refine_options={"iterations": 30})
    assert refined.score["total"] <= refined.search_score["total"]


def test_refine_towards_another_program(tmp_path):
    prog, goal = tmp_path / "prog.json", tmp_path / "goal.json"
    prog.write_text(PROGRAM)
    goal.write_text(PROGRAM.replace('"radius": 0.25', '"radius": 0.3')
                    .replace("[0.1, 0.05, 0]", "[0.18, -0.02, 0]"))
    r = fuzzycsg.refine(prog, goal, views=2, size=48, iterations=40, lr=0.005, threads=2)
    assert r.target_kind == "model" and r.loss[-1] < r.loss[0]
    radius = r.tree.get("root.children[1].radius")[0]
    assert radius > 0.25
    with pytest.raises(fuzzycsg.OptionError, match="^views: must be in"):
        fuzzycsg.refine(prog, goal, views=0)


def test_errors_are_the_programs(tmp_path, program_error):
    broken = tmp_path / "broken.csg"
    broken.write_text("difference() {\n  cube(size = 2, center = true);\n  sphere(r = -1);\n}\n")
    with pytest.raises(fuzzycsg.InputError) as e:
        fuzzycsg.convert(broken)
    assert str(e.value) == program_error("convert", broken, "-o", tmp_path / "out")
    blank = tmp_path / "blank.pbm"
    blank.write_text("P1\n4 4\n" + "0 0 0 0\n" * 4)
    with pytest.raises(fuzzycsg.InputError) as e:
        fuzzycsg.fit(blank, iters=1)
    assert str(e.value) == program_error("fit", blank, "-o", tmp_path / "out2", "--iters", 1)
    with pytest.raises(TypeError, match="a path expected"):
        fuzzycsg.convert(42)


def test_render_a_picture(tmp_path):
    tree = fuzzycsg.Tree.from_json(PROGRAM)
    path = tmp_path / "r.png"
    png = fuzzycsg.render(tree, path, width=64, height=48, resolution=32,
                          camera={"eye": [3, -4, 2.5], "fov_deg": 30})
    assert png[:8] == b"\x89PNG\r\n\x1a\n" and path.read_bytes() == png
    assert int.from_bytes(png[16:20], "big") == 64 and int.from_bytes(png[20:24], "big") == 48
    with pytest.raises(fuzzycsg.InputError, match="inside"):
        fuzzycsg.render(tree, camera={"eye": [0.5, 0.4, 0.3], "target": [0, 0, 1]})
    with pytest.raises(fuzzycsg.InputError, match="3D"):
        fuzzycsg.render(fuzzycsg.Tree.from_json(DISC))


def test_convert_from_arrays_gives_the_programs_tree(tmp_path):
    """A mesh held in memory is converted as the program converts the same mesh's file."""
    import subprocess, os
    tree = fuzzycsg.Tree.from_json(PROGRAM)
    path = tmp_path / "part.obj"
    vertices, triangles = fuzzycsg.mesh(tree, path, resolution=40)
    r = fuzzycsg.convert(vertices, triangles, name="part", threads=2, seed=3, time_limit=120,
                         restarts=1, refine_steps=50)
    out = tmp_path / "out"
    subprocess.run([os.environ["FUZZYCSG_PROGRAM"], "convert", str(path), "-o", str(out),
                    "--threads", "2", "--seed", "3", "--time-limit", "120", "--restarts", "1",
                    "--refine-steps", "50", "-q"], check=True)
    from_file = fuzzycsg.Tree.read(str(out / "tree.json"))
    assert r.primitives >= 2 and r.metrics["iou"] > 0.9, (r.primitives, r.metrics)
    assert r.tree.names == from_file.names
    np.testing.assert_array_equal(r.tree.values, from_file.values)
    assert r.report["target"].startswith("mesh part:"), r.report["target"]
    # Bad arrays: named, one line.
    with pytest.raises(ValueError, match=f"^faces: entry 2 is {len(vertices)}, outside"):
        fuzzycsg.convert(vertices, np.array([[0, 1, len(vertices)]]))
    with pytest.raises(ValueError, match="vertices"):
        fuzzycsg.convert(vertices[:, :2], triangles)
    with pytest.raises(fuzzycsg.InputError, match="^part: mesh is open"):
        fuzzycsg.convert(vertices, triangles[:-1], name="part")


@pytest.mark.parametrize("threads", [100000, 10**9, -1])
def test_threads_out_of_range_are_option_errors(threads):
    """The library checks threads: no engine terminates the interpreter (oneTBB) on a huge count."""
    tree = fuzzycsg.Tree.from_json(PROGRAM)
    points = np.zeros((4, 3), np.float32)
    with pytest.raises(fuzzycsg.OptionError, match="^threads: must be in 0..256"):
        fuzzycsg.eval(tree, points, threads=threads)
    with pytest.raises(fuzzycsg.OptionError, match="^threads: must be in 0..256"):
        fuzzycsg.grad(tree, points, np.ones(4, np.float32), threads=threads)
    with pytest.raises(fuzzycsg.OptionError, match="threads: must be in 0..256"):
        fuzzycsg.mesh(tree, resolution=16, threads=threads)
    with pytest.raises(fuzzycsg.OptionError, match="threads: must be in 0..256"):
        fuzzycsg.fit(tree, prims=2, iters=2, threads=threads)
    vertices, triangles = fuzzycsg.mesh(tree, resolution=16)
    with pytest.raises(fuzzycsg.OptionError, match="^threads: must be in 0..256"):
        fuzzycsg.convert(vertices, triangles, threads=threads)


def _interrupt_after(seconds):
    import os, signal, threading
    timer = threading.Timer(seconds, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    return timer


def test_ctrl_c_interrupts_the_engines_and_leaves_them_usable(source):
    """SIGINT during an engine call raises KeyboardInterrupt once the engine has stopped at its
    next step (a fit of ten million steps, a conversion of a CAD part), and the next call runs."""
    import time
    disc = fuzzycsg.Tree.from_json(DISC)
    start = time.monotonic()
    _interrupt_after(1.0)
    with pytest.raises(KeyboardInterrupt):
        fuzzycsg.fit(disc, prims=4, iters=10**7, batch=512, threads=2,
                     metrics={"points": 20000, "chamfer": False})
    assert time.monotonic() - start < 60  # ten million steps take hours
    mesh = source / "tests" / "data" / "meshes" / "cad" / "cgal_couplingdown.off"
    _interrupt_after(1.0)
    with pytest.raises(KeyboardInterrupt):
        fuzzycsg.convert(mesh, threads=2, time_limit=3600)
    r = fuzzycsg.fit(disc, prims=4, iters=20, batch=256, threads=2,
                     metrics={"points": 2000, "chamfer": False})
    assert r.steps == 20
