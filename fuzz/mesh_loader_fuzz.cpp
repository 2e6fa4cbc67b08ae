// libFuzzer target: the first byte chooses the format (.off, .obj, .stl, .ply), the rest is
// written to a file of that extension and read as a mesh (read_mesh_file: assimp, then our own
// checks of header counts, finiteness, indices and the compaction of used vertices); a small
// mesh that reads is also loaded as a target (normalisation, Embree scene, closedness test).
// InputError with one line is the expected answer to bad input; any other exception, a crash
// or a sanitizer report is a bug. A mesh that reads has triangles whose corners are vertices,
// every vertex used and finite; a target that loads answers occupancy with 0 or 1 and samples
// finite boundary points inside the normalised box.
//
// assimp parses the formats (a Debian shared library, not instrumented) and has bugs of its own
// that a few mutations reach (segmentation faults, failed assertions, endless loops on corrupt
// files): every input is first read in a helper process (fuzz::TrialRunner), and one that kills
// it with libassimp on the stack is skipped (counted at exit) instead of reported. Any other
// death is reproduced in the fuzzer's process and reported.
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <random>
#include <string>
#include <string_view>
#include <vector>

#include "fuzz_support.hpp"
#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/target/mesh_file.hpp"
#include "fuzzycsg/target/target.hpp"

namespace {

constexpr const char* kTarget = "mesh_loader_fuzz";
using fuzzycsg::fuzz::bug;

// Meshes up to this many triangles are also loaded as targets (Embree; the closedness test
// casts 7 rays from each of 16384 points).
constexpr std::size_t kMaxTargetTriangles = 4096;

void check_mesh(const fuzzycsg::TriangleMesh& mesh) {
  if (mesh.triangles.empty()) bug(kTarget, "a mesh without triangles was read");
  const std::size_t nv = mesh.vertices.size();
  std::vector<bool> used(nv, false);
  for (const std::array<int, 3>& t : mesh.triangles) {
    for (const int v : t) {
      if (v < 0 || static_cast<std::size_t>(v) >= nv)
        bug(kTarget,
            "a triangle refers to vertex " + std::to_string(v) + " of " + std::to_string(nv));
      used[static_cast<std::size_t>(v)] = true;
    }
  }
  for (std::size_t v = 0; v < nv; ++v) {
    if (!used[v]) bug(kTarget, "vertex " + std::to_string(v) + " is used by no triangle");
  }
  for (const std::array<double, 3>& p : mesh.vertices) {
    for (const double x : p) {
      if (!std::isfinite(x)) bug(kTarget, "a vertex coordinate is not finite");
    }
  }
}

void check_target(const fuzzycsg::Target& target) {
  if (target.dim() != 3 || target.kind() != "mesh") bug(kTarget, "a mesh target that is not 3D");
  const fuzzycsg::Similarity s = target.normalisation();
  if (!(std::isfinite(s.scale) && s.scale > 0)) bug(kTarget, "the normalisation's scale is bad");
  const std::vector<float> points = {0, 0, 0, 0.5f, -0.5f, 0.25f, -1, 1, -1, 0.9f, 0.1f, -0.3f};
  // Normalised with padding 0.2: every vertex within [-0.8, 0.8] (up to float rounding).
  fuzzycsg::fuzz::check_crisp_target(kTarget, target, points, 0.8f + 1e-5f);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace fuzzycsg;
  static const fuzz::ScratchDir scratch(kTarget);
  if (size < 1) return 0;
  static constexpr std::array<const char*, 4> kNames = {"m.off", "m.obj", "m.stl", "m.ply"};
  const std::string_view bytes(reinterpret_cast<const char*>(data + 1), size - 1);
  const std::filesystem::path path = scratch.write(kNames[data[0] % kNames.size()], bytes);

  static fuzz::SkipCounter skipped(kTarget, "assimp itself crashed, aborted or hung on them");
  static fuzz::TrialRunner assimp("libassimp", 3,
                                  [](const std::string& file) { read_mesh_file(file); });
  if (assimp.run(path.string()) == fuzz::Trial::kDiedInLibrary) {
    skipped.add();
    return -1;  // not kept in the corpus
  }

  TriangleMesh mesh;
  try {
    mesh = read_mesh_file(path);
  } catch (const InputError& e) {
    fuzz::check_message(kTarget, e);
    return 0;
  }
  check_mesh(mesh);
  if (mesh.triangles.size() > kMaxTargetTriangles) return 0;

  TargetOptions options;
  options.threads = 1;
  std::unique_ptr<Target> target;
  try {
    target = load_target(path.string(), options);
  } catch (const InputError& e) {
    fuzz::check_message(kTarget, e);
    return 0;
  }
  check_target(*target);
  return 0;
}
