// opencsg_bench: the forward pass of CSG of meshed primitives by rays
// (diffcsg::render_visibility) against OpenCSG drawing the same triangles through the same
// camera (fuzzycsg/opencsg: Mesa's llvmpipe through surfaceless EGL, on the same CPU), at
// 512 x 512 on the models of raster_bench:
//   small  a cube less a cylinder of 29 sides, with a bar through it: 136 triangles;
//   large  OpenSCAD's example001 (a ball less three cylinders; $fa = 12, $fs = 2): 1,244
//          triangles;
//   dense  OpenSCAD's logo (the same with $fn = 100): 10,640 triangles.
// For each: milliseconds per frame (median of RUNS frames after one warm-up) of
// render_visibility into a frame it reuses with every hardware thread and with one, and into a
// new frame (8 MB to allocate and fault in) with every thread; of OpenCSG with Goldfeather and
// with SCS, drawing only (to glFinish) and drawing plus reading the primitive ids back; the
// ratio of ours (every thread) to the faster OpenCSG algorithm with readback (the same output:
// the visible primitive per pixel in memory) and to drawing only; and the pixels where the two
// images name different primitives.
//
//   opencsg_bench [RUNS]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <thread>
#include <vector>

#include "fuzzycsg/diffcsg/openscad_csg.hpp"
#include "fuzzycsg/diffcsg/visibility.hpp"
#include "fuzzycsg/opencsg/renderer.hpp"

using namespace fuzzycsg::diffcsg;
namespace gl = fuzzycsg::opencsg;

namespace {

double median_ms(int runs, const std::function<void()>& f) {
  f();  // warm-up
  std::vector<double> ms;
  for (int r = 0; r < runs; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    ms.push_back(
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
  }
  std::sort(ms.begin(), ms.end());
  return ms[ms.size() / 2];
}

Camera view(const Scene& scene) {
  double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};
  for (const TriMesh& t : scene.primitives) {
    for (const Vec3& v : t.vertices) {
      for (int k = 0; k < 3; ++k) {
        lo[k] = std::min(lo[k], v[static_cast<std::size_t>(k)]);
        hi[k] = std::max(hi[k], v[static_cast<std::size_t>(k)]);
      }
    }
  }
  const Vec3 centre{(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2};
  const double size = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
  return Camera::orbit(centre, 30, 30, 3 * size, 512, 512, 30);
}

}  // namespace

int main(int argc, char** argv) {
  const int runs = argc > 1 ? std::max(1, std::atoi(argv[1])) : 9;
  const int hw = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  const std::filesystem::path scad =
      std::filesystem::path(FUZZYCSG_SOURCE_DIR) / "../shared/data/scad";
  struct Model {
    const char* name;
    Scene scene;
  };
  std::vector<Model> models;
  models.push_back(
      {"small", parse_openscad_csg("union() { difference() { cube(size = [2, 2, 2], center = true);"
                                   " cylinder($fn = 29, h = 3, r = 0.6, center = true); }"
                                   " cube(size = [0.5, 0.5, 3], center = true); }",
                                   "small")});
  models.push_back({"large", read_openscad_csg(scad / "Old/example001.openscad.csg")});
  models.push_back({"dense", read_openscad_csg(scad / "Basics/logo.openscad.csg")});
  gl::Renderer opencsg(512, 512);
  std::printf("512x512, %d hardware threads, median of %d frames; OpenCSG 1.5 on %s\n", hw, runs,
              opencsg.description().c_str());
  std::printf(
      "model  triangles | ours: %d threads, 1 thread, %d threads new frame | OpenCSG Goldfeather: "
      "draw, +read | SCS: draw, +read | ratio ours (%d threads) / faster OpenCSG: +read, draw | "
      "pixels differing\n",
      hw, hw, hw);
  for (const Model& m : models) {
    const Camera cam = view(m.scene);
    Frame frame;
    const double ours = median_ms(runs, [&] { render_visibility(m.scene, cam, frame, hw); });
    const double ours1 = median_ms(runs, [&] { render_visibility(m.scene, cam, frame, 1); });
    const double fresh = median_ms(runs, [&] { frame = render_visibility(m.scene, cam, hw); });
    opencsg.set_scene(m.scene);
    double draw[2], read[2];
    std::vector<int> ids;
    for (const gl::Algorithm a : {gl::Algorithm::kGoldfeather, gl::Algorithm::kScs}) {
      const int k = a == gl::Algorithm::kScs ? 1 : 0;
      draw[k] = median_ms(runs, [&] { opencsg.draw(cam, a); });
      read[k] = median_ms(runs, [&] { ids = opencsg.render(cam, a); });
    }
    int differ = 0;
    for (std::size_t px = 0; px < ids.size(); ++px) differ += ids[px] != frame.primitive[px];
    const double best_read = std::min(read[0], read[1]), best_draw = std::min(draw[0], draw[1]);
    std::printf(
        "%-6s %9zu | %6.1f ms %6.1f ms %6.1f ms | %6.1f ms %6.1f ms | %6.1f ms %6.1f ms | %5.2fx "
        "%5.2fx | %d of %d\n",
        m.name, m.scene.triangle_count(), ours, ours1, fresh, draw[0], read[0], draw[1], read[1],
        ours / best_read, ours / best_draw, differ, frame.visible_pixels());
  }
  return 0;
}
