// fuzzycsg mesh TREE -o OUT [--resolution N] [--brick N] [--no-prune] [--threads N] [--check]
//
// The tree's 0.5 level set: a closed, oriented triangle mesh (OBJ, STL, PLY) of a 3D tree, closed
// contours (SVG, OBJ polylines) of a 2D one. Prints the counts and how much of the grid was
// evaluated; --check reads the mesh file back and counts what keeps it from being a closed,
// oriented 2-manifold.

#include <fmt/format.h>

#include <memory>
#include <string>

#include "commands.hpp"
#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/io/tree_json.hpp"
#include "fuzzycsg/mesh/mesh.hpp"

namespace fuzzycsg::app {

namespace {

struct MeshArgs {
  std::string tree, out;
  MeshOptions options;
  bool no_prune = false;
  bool allow_empty = false;
  bool check = false;
  bool no_simplify = false;
};

void print_stats(const MeshStats& s, const std::string& what) {
  fmt::print(
      "mesh: {}; grid {}; evaluated {} of {} grid points ({:.1f}%) in {} bricks (mean "
      "{:.1f} leaves each, {} points rechecked), {:.3f} s\n",
      what,
      s.cells[2] > 0 ? fmt::format("{}x{}x{}", s.cells[0], s.cells[1], s.cells[2])
                     : fmt::format("{}x{}", s.cells[0], s.cells[1]),
      s.points_evaluated, s.grid_points,
      100.0 * static_cast<double>(s.points_evaluated) /
          static_cast<double>(std::max<std::size_t>(s.grid_points, 1)),
      s.bricks,
      static_cast<double>(s.leaves_evaluated) /
          static_cast<double>(std::max<std::size_t>(s.bricks, 1)),
      s.points_rechecked, s.seconds);
}

// --check: the file just written, read back and judged by its positions (as a reader that
// welds coincident vertices sees it), not the mesh in memory, whose indices can hide vertices
// at one position. An empty mesh (--allow-empty) is judged as it is.
void print_check(const TriangleMesh& written, const std::string& path) {
  const MeshCheck c = check_mesh(written.triangles.empty() ? written : read_triangle_mesh(path));
  fmt::print(
      "mesh: check of {} as written: {} vertices by position, {} triangles, {} edges; {} "
      "degenerate triangles, {} edges not in exactly two triangles, {} misoriented edges, {} "
      "non-manifold vertices{}\n",
      path, c.vertices, c.triangles, c.edges, c.degenerate_triangles, c.nonmanifold_edges,
      c.misoriented_edges, c.nonmanifold_vertices,
      c.triangles == 0               ? " (empty)"
      : c.closed_oriented_manifold() ? " (a closed, oriented 2-manifold)"
                                     : "");
}

int run_mesh(MeshArgs a) {
  const Tree tree = io::read_tree_file(a.tree);
  a.options.prune = !a.no_prune;
  a.options.simplify = !a.no_simplify;
  const auto wrap = [&](const InputError& e) {
    return InputError(fmt::format("{}: {}", a.tree, e.what()));
  };
  // An empty level set is an error unless asked for: nothing is written.
  const auto refuse_empty = [&](const char* what) {
    if (a.allow_empty) return;
    throw InputError(fmt::format(
        "{}: the 0.5 level set is empty in the domain at resolution {} (nothing written; "
        "--allow-empty writes an empty {})",
        a.tree, a.options.resolution, what));
  };
  MeshStats stats;
  if (tree.dim == 3) {
    TriangleMesh mesh;
    try {
      mesh = extract_mesh(tree, tree.params.values(), a.options, &stats);
    } catch (const InputError& e) {
      throw wrap(e);
    }
    if (mesh.triangles.empty()) refuse_empty("mesh");
    write_mesh(mesh, a.out);
    print_stats(stats, fmt::format("{} vertices, {} triangles, volume {:.6g}", mesh.vertices.size(),
                                   mesh.triangles.size(), signed_volume(mesh)));
    if (a.check) print_check(mesh, a.out);
  } else {
    Contours contours;
    try {
      contours = extract_contours(tree, tree.params.values(), a.options, &stats);
    } catch (const InputError& e) {
      throw wrap(e);
    }
    if (contours.loops.empty()) refuse_empty("file");
    write_contours(contours, tree, a.out);
    print_stats(stats, fmt::format("{} loops, area {:.6g}", contours.loops.size(),
                                   contours_area(contours)));
  }
  return 0;
}

}  // namespace

Verb register_mesh(CLI::App& app) {
  auto a = std::make_shared<MeshArgs>();
  CLI::App* cmd =
      app.add_subcommand("mesh", "The 0.5 level set: a closed triangle mesh (3D) or contours (2D)");
  cmd->add_option("tree", a->tree, "Tree file")->required();
  cmd->add_option("-o,--output", a->out,
                  "Output: .obj, .stl or .ply (3D); .svg or .obj polylines (2D)")
      ->required();
  cmd->add_option("--resolution", a->options.resolution,
                  "Grid cells along the domain's longest side")
      ->capture_default_str()
      ->check(CLI::Range(1, kMaxMeshResolution));
  cmd->add_option("--brick", a->options.brick, "Cells per axis of the blocks evaluated densely")
      ->capture_default_str()
      ->check(CLI::Range(1, 64));
  cmd->add_flag("--no-prune", a->no_prune,
                "Evaluate every grid point (no interval bounds; the same result, slower)");
  cmd->add_flag("--allow-empty", a->allow_empty,
                "Write an empty mesh when the level set is empty (default: an error)");
  cmd->add_flag("--no-simplify", a->no_simplify,
                "Evaluate the whole tree in every brick (bounds only; the same result)");
  cmd->add_flag("--check", a->check,
                "Read the file back, weld vertices at one position and count degenerate "
                "triangles, edges not in two oppositely oriented triangles, non-manifold vertices");
  add_threads_option(cmd, a->options.threads);
  return {cmd, [a] { return run_mesh(*a); }};
}

}  // namespace fuzzycsg::app
