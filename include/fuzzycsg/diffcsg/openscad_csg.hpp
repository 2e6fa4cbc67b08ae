#pragma once
// OpenSCAD models (the flattened CSG form that `openscad -o model.csg model.scad` writes, read by
// the scad module's importer, scad/openscad_csg.hpp) for DiffCSG: as a Scene of meshed
// primitives (scene.hpp), and as a tree with the tessellation that reproduces OpenSCAD's.
//
// Spheres and cylinders are tessellated as OpenSCAD 2021.01 does: a sphere is
// (fragments + 1) / 2 rings of latitude with capping polygons, a cylinder two circles of that
// many points (a cone's apex is one point). A primitive whose placement leaves it no volume is
// refused naming its line.

#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>

#include "fuzzycsg/diffcsg/scene.hpp"
#include "fuzzycsg/scad/openscad_csg.hpp"

namespace fuzzycsg::diffcsg {

Scene scene_from_csg(const scad::CsgModel& model);
Scene read_openscad_csg(const std::filesystem::path& path);
// `source` names the text in messages.
Scene parse_openscad_csg(std::string_view text, const std::string& source,
                         std::size_t max_triangles = scad::kMaxOpenscadTriangles);

// The model as a tree (scad::csg_tree), for refinement, with the tessellation that keeps
// OpenSCAD's fragments for every sphere and cylinder.
struct OpenscadModel {
  Tree tree;
  TessellationOptions tessellation;
};
OpenscadModel openscad_model(const scad::CsgModel& model);
OpenscadModel read_openscad_csg_tree(const std::filesystem::path& path);
OpenscadModel parse_openscad_csg_tree(std::string_view text, const std::string& source,
                                      std::size_t max_triangles = scad::kMaxOpenscadTriangles);

}  // namespace fuzzycsg::diffcsg
