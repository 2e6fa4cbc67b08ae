#pragma once
// The scenes the DiffCSG benchmarks share: raster_bench, opencsg_bench, diffcsg_step_bench.

namespace fuzzycsg::bench {

// A cube less a cylinder of 29 sides, with a bar through it: 136 triangles as OpenSCAD's .csg
// (140 as a tree file, whose cylinder caps are fans from a centre), near the 128 of DiffCSG's
// Table 1.
inline constexpr const char* kSmallScene =
    "union() { difference() { cube(size = [2, 2, 2], center = true);"
    " cylinder($fn = 29, h = 3, r = 0.6, center = true); }"
    " cube(size = [0.5, 0.5, 3], center = true); }";

}  // namespace fuzzycsg::bench
