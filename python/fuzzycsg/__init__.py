"""fuzzycsg: fuzzy CSG trees, their evaluation and gradients, and the engines that make them.

    import fuzzycsg
    tree = fuzzycsg.Tree.read("examples/box_with_hole.json")
    occupancy = fuzzycsg.eval(tree, points)            # float32, one per point
    loss, g = fuzzycsg.grad(tree, points, weights)     # d(sum_i w_i o_i) / d params
    result = fuzzycsg.convert("part.stl", time_limit=60)
    print(result.scad)

Every engine takes its options as keyword arguments named as the library's options structs
spell them (see ``help(fuzzycsg.FitOptions)``, ``fuzzycsg.options(fuzzycsg.FitOptions)``), and
returns a result object. Errors are ``fuzzycsg.InputError`` (a ValueError) with the one-line
message the ``fuzzycsg`` program prints; an option out of range is an ``OptionError`` naming it.
The GIL is released while the C++ code runs. The differentiable layer for PyTorch is
``fuzzycsg.torch``.
"""

from __future__ import annotations

import json
import os
import types

from . import _fuzzycsg
from ._fuzzycsg import (  # noqa: F401  (the module's public names)
    ConvertOptions,
    Error,
    ExportOptions,
    FitOptions,
    InputError,
    MeshOptions,
    MetricsOptions,
    OptionError,
    Camera,
    PruneOptions,
    RefineOptions,
    RenderOptions,
    SamplingOptions,
    TargetOptions,
    TargetViewOptions,
    TraceLocalOptions,
    TraceOptions,
    TraceRefineOptions,
    Tree,
    TreeLayer,
    eval,
    full_binary_tree,
    grad,
)
from ._options import fields, options_from

__version__ = "0.1.0"


class Result(types.SimpleNamespace):
    """An engine's result: its fields as attributes."""


def options(cls) -> dict:
    """The options of an engine (``fuzzycsg.FitOptions``, ...) with their defaults."""
    return fields(cls())


def _split(kwargs: dict, names) -> dict:
    return {k: kwargs.pop(k) for k in list(kwargs) if k in names}


def fit(target, **kwargs) -> Result:
    """Inverse CSG (Liu et al. 2024): a full binary tree fitted to ``target`` (a mesh, picture or
    tree file, or a ``Tree``). Options: the fields of ``FitOptions``, plus ``padding`` and
    ``image_resolution`` (``TargetOptions``). Returns ``trained``, ``snapped`` and ``pruned``
    trees in the target's coordinates, ``loss_curve`` (rows: step, loss, seconds), ``metrics_*``
    and ``stop``."""
    target_options = options_from(
        TargetOptions, _split(kwargs, ("padding", "image_resolution")), "fit"
    )
    fit_options = options_from(FitOptions, kwargs, "fit")
    target_options.threads = fit_options.threads
    return Result(**_fuzzycsg._fit(_path_or_tree(target), fit_options, target_options))


def convert(target, faces=None, *, name: str = "mesh", **kwargs) -> Result:
    """A mesh, an OpenSCAD ``.csg`` model or a picture to a crisp CSG program of CAD primitives.
    ``target``: a file, or a mesh held in memory as ``convert(vertices, faces)`` (V x 3
    coordinates in the mesh's units, F x 3 vertex indices of its triangles; ``name`` stands for
    it in errors and the report), converted as a file of the same mesh is. Options: the fields
    of ``ConvertOptions``. Returns ``tree``, ``scad`` (the OpenSCAD program), ``primitives``,
    ``metrics``, ``chamfer``, ``hausdorff``, ``reached`` and ``report`` (a dict, report.json's
    content)."""
    options = options_from(ConvertOptions, kwargs, "convert")
    if faces is not None:
        result = _fuzzycsg._convert_mesh(target, faces, options, name)
    else:
        result = _fuzzycsg._convert(_path(target), options)
    result["report"] = json.loads(result["report"])
    return Result(**result)


def prune(tree: Tree, points=None, *, seed: int = 0, count: int = 65536, **kwargs):
    """Snaps a tree's operators and removes its redundant nodes, judged at ``points`` (N x dim;
    default: ``count`` uniform points in [-1, 1]^dim drawn with ``seed``). Options: the fields of
    ``PruneOptions``. Returns ``(tree, report)``."""
    if not isinstance(tree, Tree):
        raise TypeError("prune(): tree: a fuzzycsg.Tree expected")
    return _fuzzycsg._prune(tree, points, options_from(PruneOptions, kwargs, "prune"), seed, count)


def trace(picture, *, refine: bool = False, refine_options: dict | None = None, **kwargs) -> Result:
    """Gibson et al.'s search for a crisp 2D CSG tree of a picture (PNG, ...), optionally refined
    by gradient descent (``refine=True``, ``refine_options``: the fields of
    ``TraceRefineOptions``). Options: the fields of ``TraceOptions``. Returns ``tree`` (in pixel
    units), ``score`` and the search's statistics."""
    so = options_from(TraceOptions, kwargs, "trace")
    ro = options_from(TraceRefineOptions, refine_options or {}, "trace")
    return Result(**_fuzzycsg._trace(_path(picture), so, refine, ro))


_VIEW_FIELDS = ("shading", "views", "size", "elevation", "distance", "fov")


def refine(model, target, *, sphere_subdivisions: int = 2, cylinder_segments: int = 16,
           **kwargs) -> Result:
    """DiffCSG: a model's continuous parameters refined so that its renderings match
    ``target``'s (a model, a mesh, or a views file). ``model``: a tree file, an OpenSCAD .csg or a
    ``Tree``. Options: the fields of ``RefineOptions`` and of ``TargetViewOptions`` (``views``,
    ``size``, ``shading``, ...). Returns ``tree``, ``loss`` (per step), ``converged``."""
    view_kwargs = _split(kwargs, _VIEW_FIELDS)
    vo = options_from(TargetViewOptions, view_kwargs, "refine")
    vo.size_given = "size" in view_kwargs
    ro = options_from(RefineOptions, kwargs, "refine")
    vo.threads = ro.threads
    return Result(
        **_fuzzycsg._refine(_path_or_tree(model), _path(target), ro, vo, sphere_subdivisions,
                            cylinder_segments)
    )


def mesh(tree: Tree, path=None, **kwargs):
    """The tree's 0.5 level set: ``(vertices, triangles)`` (float64 V x 3, int32 F x 3) in 3D,
    also written to ``path`` (OBJ, STL, PLY) when given; a list of closed loops (L x 2) in 2D.
    Options: the fields of ``MeshOptions``."""
    if not isinstance(tree, Tree):
        raise TypeError("mesh(): tree: a fuzzycsg.Tree expected")
    return _fuzzycsg._mesh(tree, options_from(MeshOptions, kwargs, "mesh"),
                           None if path is None else _path(path))


def export(tree: Tree, path=None, **kwargs) -> str:
    """The OpenSCAD program of the tree's crisp counterpart (also written to ``path`` when
    given). Options: the fields of ``ExportOptions``. ``export_report`` gives the report."""
    text, _ = _export(tree, kwargs)
    if path is not None:
        _write_atomic(_path(path), text)
    return text


def export_report(tree: Tree, **kwargs) -> dict:
    """What ``export`` made of each leaf (report.json of ``fuzzycsg export``)."""
    return json.loads(_export(tree, kwargs)[1])


def render(tree: Tree, path=None, *, camera: dict | None = None, **kwargs) -> bytes:
    """A PNG picture of a 3D tree's 0.5 level set (as ``fuzzycsg render``), also written to
    ``path`` when given. ``camera``: a dict of ``eye``, ``target``, ``up``, ``fov_deg`` (default:
    cameras framing the shape). Options: the fields of ``RenderOptions``."""
    if not isinstance(tree, Tree):
        raise TypeError("render(): tree: a fuzzycsg.Tree expected")
    options = options_from(RenderOptions, kwargs, "render")
    if camera is not None:
        options.camera = options_from(Camera, camera, "render")
    png = _fuzzycsg._render(tree, options)
    if path is not None:
        _write_atomic_bytes(_path(path), png)
    return png


def _export(tree, kwargs):
    if not isinstance(tree, Tree):
        raise TypeError("export(): tree: a fuzzycsg.Tree expected")
    return _fuzzycsg._export(tree, options_from(ExportOptions, kwargs, "export"))


def _path(p) -> str:
    if isinstance(p, (str, os.PathLike)):
        return os.fspath(p)
    raise TypeError(f"a path expected, got {type(p).__name__}")


def _path_or_tree(p):
    return p if isinstance(p, Tree) else _path(p)


def _write_atomic(path: str, text: str) -> None:
    _write_atomic_bytes(path, text.encode("utf-8"))


def _write_atomic_bytes(path: str, data: bytes) -> None:
    tmp = f"{path}.tmp{os.getpid()}"
    try:
        with open(tmp, "wb") as f:
            f.write(data)
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.remove(tmp)
