#include "convert/csg_input.hpp"

#include <algorithm>
#include <cmath>

#include "convert/solid.hpp"
#include "fuzzycsg/convert/convert.hpp"
#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/core/logic.hpp"
#include "fuzzycsg/core/tree_builder.hpp"
#include "fuzzycsg/mesh/mesh.hpp"
#include "fuzzycsg/scad/openscad_csg.hpp"

namespace fuzzycsg::convert {

namespace {

// The tree's structure with sigmoid leaves of sharpness `k` and min/max booleans: its occupancy
// is the sigmoid of the booleans' signed distance, so its 0.5 level set is the crisp tree's
// boundary and it varies smoothly enough across a cell for marching cubes to place it.
int soft_rebuild(const Tree& tree, const std::vector<double>& params, int node, double k,
                 TreeBuilder& b) {
  const Node& n = tree.node(node);
  if (n.kind == NodeKind::kPrimitive) {
    return add_leaf(b, *solid_of_leaf(tree, params, node), k);  // leaf_bounds checked it
  }
  std::vector<int> children;
  for (const int c : n.children) children.push_back(soft_rebuild(tree, params, c, k, b));
  const int op = b.op(n.op, std::move(children));
  if (n.op != OpKind::kComplement) b.logic(op, logic::Family::kGodel);
  return op;
}

// A box around every bounded leaf (the solid lies within their union), in world coordinates.
// Throws InputError naming the first leaf that is not one of convert's solids.
Eigen::AlignedBox3d leaf_bounds(const Tree& tree, const std::vector<double>& params,
                                const std::string& path) {
  Eigen::AlignedBox3d box;
  for (int i = 0; i < static_cast<int>(tree.nodes.size()); ++i) {
    const Node& n = tree.node(i);
    if (n.kind != NodeKind::kPrimitive) continue;
    const std::optional<Solid> s = solid_of_leaf(tree, params, i);
    if (!s) {
      throw InputError(path + ": " + n.name + ": " +
                       std::string(primitive_info(n.shape.type).name) +
                       "; convert takes boxes, cylinders, cones, spheres and tori");
    }
    if (s->kind == SolidKind::kHalfSpace) continue;
    const Eigen::AlignedBox3d local = s->local_bounds();
    for (int c = 0; c < 8; ++c) {
      box.extend(s->rotation * local.corner(static_cast<Eigen::AlignedBox3d::CornerType>(c)) +
                 s->centre);
    }
  }
  return box;
}

// The tree's 0.5 level set meshed over its domain, or where it has none its leaves' bounds,
// `resolution` cells along their longest side; `source` names the tree in messages.
TriangleMesh level_set_mesh(const Tree& tree, const std::string& source, int resolution,
                            int threads) {
  const std::vector<double> params = tree.params.values();
  Eigen::AlignedBox3d bounds = leaf_bounds(tree, params, source);
  if (tree.domain) {
    bounds = Eigen::AlignedBox3d(
        Eigen::Vector3d(tree.domain->min[0], tree.domain->min[1], tree.domain->min[2]),
        Eigen::Vector3d(tree.domain->max[0], tree.domain->max[1], tree.domain->max[2]));
  }
  if (bounds.isEmpty() || !(bounds.sizes().maxCoeff() > 0)) {
    throw InputError(source + ": the model has no bounded solid");
  }
  const double cell = bounds.sizes().maxCoeff() / resolution;
  TreeBuilder b(3);
  const int root = soft_rebuild(tree, params, tree.root, 2.0 / cell, b);
  const Eigen::Vector3d lo = bounds.min().array() - 2 * cell, hi = bounds.max().array() + 2 * cell;
  b.set_domain(Domain{{lo[0], lo[1], lo[2]}, {hi[0], hi[1], hi[2]}});
  const Tree soft = std::move(b).finish(root, source);
  MeshOptions mesh_options;
  mesh_options.resolution = resolution + 4;
  mesh_options.threads = threads;
  return extract_mesh(soft, soft.params.values(), mesh_options);
}

}  // namespace

Tree smooth_tree(const Tree& tree, double sharpness) {
  const std::vector<double> params = tree.params.values();
  leaf_bounds(tree, params, "convert");  // every leaf a solid
  TreeBuilder b(3);
  const int root = soft_rebuild(tree, params, tree.root, sharpness, b);
  if (tree.domain) b.set_domain(*tree.domain);
  return std::move(b).finish(root, "convert");
}

TriangleMesh solid_mesh(const Tree& tree, int resolution, int threads) {
  return level_set_mesh(tree, "convert", resolution, threads);
}

CsgInput read_csg_input(const std::string& path, double padding, int resolution, int threads) {
  Tree crisp = scad::csg_tree(scad::read_csg(path)).tree;
  CsgInput in;
  in.mesh = level_set_mesh(crisp, path, resolution, threads);
  if (in.mesh.triangles.empty()) throw InputError(path + ": the model encloses no volume");
  // The cube that a mesh of the model would be normalised by (TargetOptions::padding).
  const auto [mesh_lo, mesh_hi] = bounding_box(in.mesh);
  double half = 0;
  std::array<double, 3> centre{};
  for (std::size_t a = 0; a < 3; ++a) {
    centre[a] = 0.5 * (mesh_lo[a] + mesh_hi[a]);
    half = std::max(half, 0.5 * (mesh_hi[a] - mesh_lo[a]));
  }
  half /= 1.0 - padding;
  Domain cube;
  for (std::size_t a = 0; a < 3; ++a) {
    cube.min[a] = centre[a] - half;
    cube.max[a] = centre[a] + half;
  }
  crisp.domain = cube;
  in.solid = std::move(crisp);
  return in;
}

}  // namespace fuzzycsg::convert
