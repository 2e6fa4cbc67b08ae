#pragma once
// The convert module: a 3D mesh to an editable CSG program of CAD primitives (box, cylinder,
// cone, sphere, torus, half-space), crisp, in the mesh's own coordinates. This header is its
// main one.

namespace fuzzycsg::convert {}  // namespace fuzzycsg::convert
