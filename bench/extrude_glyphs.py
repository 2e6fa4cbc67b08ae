#!/usr/bin/env python3
"""Extrude binary PBM bitmaps into closed 3D meshes (OFF) for the Fig. 12 study.

Each set pixel becomes a column of height --depth pixels; the mesh is the boundary of the union
of those columns (top and bottom faces of every set pixel, and a side wherever a set pixel meets
an unset one), with shared vertices and outward normals. Pixels that touch only at a corner give
non-manifold edges, which the fitter's inside test copes with like any other CAD mesh.

This lets the study fit the same shapes in 2D (conics on the bitmap) and in 3D (quadrics on the
extrusion) with one sampler, so the dimension is separated from the kind of shape.

    /usr/bin/python3 bench/extrude_glyphs.py --out DIR $FUZZYCSG_DATA/glyphs/A.pbm ...
"""

import argparse
import os
import sys

import numpy as np


def read_pbm(path):
    """Reads a P1 (ASCII) or P4 (binary) PBM; returns a bool array, True where set (black)."""
    with open(path, "rb") as f:
        data = f.read()
    tokens = []
    pos = 0
    while len(tokens) < 3:
        while pos < len(data) and chr(data[pos]).isspace():
            pos += 1
        if pos < len(data) and data[pos:pos + 1] == b"#":
            while pos < len(data) and data[pos:pos + 1] != b"\n":
                pos += 1
            continue
        start = pos
        while pos < len(data) and not chr(data[pos]).isspace():
            pos += 1
        if start == pos:
            raise ValueError(f"{path}: truncated PBM header")
        tokens.append(data[start:pos].decode("ascii"))
    magic, w, h = tokens[0], int(tokens[1]), int(tokens[2])
    if w <= 0 or h <= 0:
        raise ValueError(f"{path}: width and height must be positive")
    if magic == "P4":
        pos += 1  # the single whitespace byte after the header
        row = (w + 7) // 8
        raw = np.frombuffer(data, dtype=np.uint8, count=row * h, offset=pos)
        return np.unpackbits(raw.reshape(h, row), axis=1)[:, :w].astype(bool)
    if magic == "P1":
        bits = [c for c in data[pos:].decode("ascii") if c in "01"]
        if len(bits) < w * h:
            raise ValueError(f"{path}: {len(bits)} pixels, expected {w * h}")
        return np.array(bits[:w * h], dtype=np.uint8).reshape(h, w).astype(bool)
    raise ValueError(f"{path}: magic {magic!r} is not a PBM (P1 or P4)")


def extrude(img, depth):
    """Returns (vertices, quads) of the boundary of the extruded set pixels."""
    h, w = img.shape
    pad = np.zeros((h + 2, w + 2), dtype=bool)
    pad[1:-1, 1:-1] = img
    index = {}
    verts = []

    def v(x, y, z):
        key = (x, y, z)
        if key not in index:
            index[key] = len(verts)
            verts.append(key)
        return index[key]

    quads = []
    for r, c in zip(*np.nonzero(img)):
        x, y = int(c), int(h - 1 - r)  # row 0 at the top of the picture
        d = depth
        quads.append((v(x, y, d), v(x + 1, y, d), v(x + 1, y + 1, d), v(x, y + 1, d)))
        quads.append((v(x, y + 1, 0), v(x + 1, y + 1, 0), v(x + 1, y, 0), v(x, y, 0)))
        if not pad[r + 1, c + 2]:  # +x
            quads.append((v(x + 1, y, 0), v(x + 1, y + 1, 0), v(x + 1, y + 1, d), v(x + 1, y, d)))
        if not pad[r + 1, c]:  # -x
            quads.append((v(x, y, d), v(x, y + 1, d), v(x, y + 1, 0), v(x, y, 0)))
        if not pad[r, c + 1]:  # +y (the row above)
            quads.append((v(x, y + 1, 0), v(x, y + 1, d), v(x + 1, y + 1, d), v(x + 1, y + 1, 0)))
        if not pad[r + 2, c + 1]:  # -y
            quads.append((v(x + 1, y, 0), v(x + 1, y, d), v(x, y, d), v(x, y, 0)))
    return verts, quads


def write_off(path, verts, quads):
    tmp = path + ".part"
    with open(tmp, "w") as f:
        f.write(f"OFF\n{len(verts)} {2 * len(quads)} 0\n")
        for x, y, z in verts:
            f.write(f"{x} {y} {z}\n")
        for a, b, c, d in quads:
            f.write(f"3 {a} {b} {c}\n3 {a} {c} {d}\n")
    os.replace(tmp, path)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("pbm", nargs="+")
    ap.add_argument("--out", required=True, help="directory for the .off files")
    ap.add_argument("--depth", type=int, default=64, help="extrusion height in pixels")
    args = ap.parse_args()
    if args.depth <= 0:
        sys.exit("extrude_glyphs.py: --depth must be > 0")
    os.makedirs(args.out, exist_ok=True)
    for p in args.pbm:
        img = read_pbm(p)
        if not img.any():
            sys.exit(f"{p}: no set pixel to extrude")
        verts, quads = extrude(img, args.depth)
        name = os.path.splitext(os.path.basename(p))[0] + ".off"
        write_off(os.path.join(args.out, name), verts, quads)
        print(f"{name}: {len(verts)} vertices, {2 * len(quads)} triangles", file=sys.stderr)


if __name__ == "__main__":
    main()
