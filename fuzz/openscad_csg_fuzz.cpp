// libFuzzer target: any input is read as an OpenSCAD .csg model, by both readers (the meshed
// scene and the tree for refinement). InputError with one line is the expected answer to bad
// input; any other exception, a crash or a sanitizer report is a bug. A model that reads must
// also hold together: every triangle's corners are vertices of its primitive, every vertex is
// finite, every CSG node refers to nodes and primitives that exist; the tree of a model that
// reads makes a scene with the fragments the reader chose.
//
// Models are read with a budget of kMaxTriangles triangles instead of the default (2^25), so
// that an input costs milliseconds; the limit itself is checked the same way.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "fuzz_support.hpp"
#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/diffcsg/openscad_csg.hpp"
#include "fuzzycsg/diffcsg/scene.hpp"

namespace {

constexpr const char* kTarget = "openscad_csg_fuzz";
constexpr std::size_t kMaxTriangles = std::size_t{1} << 17;
using fuzzycsg::fuzz::bug;

void check_scene(const fuzzycsg::diffcsg::Scene& scene, std::string_view text) {
  using fuzzycsg::diffcsg::CsgNode;
  if (scene.primitives.empty()) bug(kTarget, "a scene without primitives was accepted", text);
  if (scene.tree_node.size() != scene.primitives.size()) {
    bug(kTarget, "tree_node does not name one node per primitive", text);
  }
  for (std::size_t p = 0; p < scene.primitives.size(); ++p) {
    const fuzzycsg::TriangleMesh& m = scene.primitives[p].mesh;
    const std::vector<int>& smoothing = scene.primitives[p].smoothing;
    if (m.triangles.empty()) bug(kTarget, "primitive " + std::to_string(p) + " has no triangles");
    if (!smoothing.empty() && smoothing.size() != m.triangles.size()) {
      bug(kTarget, "primitive " + std::to_string(p) + ": smoothing groups do not match", text);
    }
    for (const auto& t : m.triangles) {
      for (const int v : t) {
        if (v < 0 || static_cast<std::size_t>(v) >= m.vertices.size()) {
          bug(kTarget,
              "primitive " + std::to_string(p) + ": a triangle refers to vertex " +
                  std::to_string(v) + " of " + std::to_string(m.vertices.size()),
              text);
        }
      }
    }
    for (const auto& v : m.vertices) {
      if (!std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2])) {
        bug(kTarget, "primitive " + std::to_string(p) + " has a vertex that is not finite", text);
      }
    }
  }
  const auto n = static_cast<int>(scene.nodes.size());
  if (scene.root < 0 || scene.root >= n) bug(kTarget, "the root is not a node", text);
  for (int i = 0; i < n; ++i) {
    const CsgNode& node = scene.nodes[static_cast<std::size_t>(i)];
    if (node.kind == CsgNode::Kind::kPrimitive) {
      if (node.primitive < 0 ||
          static_cast<std::size_t>(node.primitive) >= scene.primitives.size()) {
        bug(kTarget, "node " + std::to_string(i) + " names no primitive", text);
      }
      continue;
    }
    if (node.kind == CsgNode::Kind::kDifference && node.children.size() != 2) {
      bug(kTarget, "a difference node without two children", text);
    }
    for (const int c : node.children) {
      // Nodes are made children first, so a child comes before its parent (no cycles).
      if (c < 0 || c >= i) bug(kTarget, "node " + std::to_string(i) + " has a bad child", text);
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace fuzzycsg;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const std::string source = "fuzz.csg";

  try {
    const diffcsg::Scene scene = diffcsg::parse_openscad_csg(text, source, kMaxTriangles);
    check_scene(scene, text);
    // The budget counts the triangles exactly: one fewer refuses the model.
    const std::size_t triangles = scene.triangle_count();
    if (triangles > kMaxTriangles) bug(kTarget, "a scene over its budget", text);
    bool refused = false;
    try {
      diffcsg::parse_openscad_csg(text, source, triangles - 1);
    } catch (const InputError& e) {
      fuzz::check_message(kTarget, e);
      refused = true;
    }
    if (!refused) bug(kTarget, "a budget of one triangle fewer than the scene's was met", text);
  } catch (const InputError& e) {
    fuzz::check_message(kTarget, e);
  }

  diffcsg::OpenscadModel model;
  try {
    model = diffcsg::parse_openscad_csg_tree(text, source, kMaxTriangles);
  } catch (const InputError& e) {
    fuzz::check_message(kTarget, e);
    return 0;
  }
  try {
    check_scene(diffcsg::scene_from_tree(model.tree, source, model.tessellation), text);
  } catch (const InputError& e) {
    bug(kTarget, std::string("the tree of a model that was read makes no scene: ") + e.what(),
        text);
  }
  return 0;
}
