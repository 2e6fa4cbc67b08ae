// opencsg_bench: the forward pass of CSG of meshed primitives by rays
// (diffcsg::render_visibility) against OpenCSG drawing the same triangles through the same
// camera (fuzzycsg/opencsg: Mesa's llvmpipe through surfaceless EGL, on the same CPU), at
// 512 x 512 on the models of raster_bench:
//   small  a cube less a cylinder of 29 sides, with a bar through it: 136 triangles;
//   large  OpenSCAD's example001 (a ball less three cylinders; $fa = 12, $fs = 2): 1,244
//          triangles;
//   dense  OpenSCAD's logo (the same with $fn = 100): 11,184 triangles.
// For each: milliseconds per frame (the median, and on a second line the minimum, of RUNS
// rounds after a warm-up, each round timing every variant once in turn, so that load from
// elsewhere slows them alike) of
// render_visibility into a frame it reuses with every hardware thread and with one, and into a
// new frame (8 MB to allocate and fault in) with every thread; of OpenCSG with Goldfeather and
// with SCS, drawing only (to glFinish) and drawing plus reading the primitive ids back; the
// ratio of ours (every thread) to the faster OpenCSG algorithm with readback (the same output:
// the visible primitive per pixel in memory) and to drawing only; and the pixels where the two
// images name different primitives.
//
//   opencsg_bench [RUNS]   (default 21)
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <thread>
#include <vector>

#include "bench/data_dir.hpp"
#include "diffcsg_scenes.hpp"
#include "fuzzycsg/diffcsg/openscad_csg.hpp"
#include "fuzzycsg/diffcsg/visibility.hpp"
#include "fuzzycsg/opencsg/renderer.hpp"

using namespace fuzzycsg::diffcsg;
namespace gl = fuzzycsg::opencsg;

namespace {

// Medians and minima of `runs` rounds; each round times every variant once, in turn, so that
// load from elsewhere slows them alike. One warm-up round first.
struct Timing {
  std::vector<double> median, min;
};
Timing time_ms(int runs, const std::vector<std::function<void()>>& variants) {
  std::vector<std::vector<double>> ms(variants.size());
  for (int r = -1; r < runs; ++r) {
    for (std::size_t v = 0; v < variants.size(); ++v) {
      const auto t0 = std::chrono::steady_clock::now();
      variants[v]();
      const auto t1 = std::chrono::steady_clock::now();
      if (r >= 0) ms[v].push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
    }
  }
  Timing out;
  for (std::vector<double>& m : ms) {
    std::sort(m.begin(), m.end());
    out.median.push_back(m[m.size() / 2]);
    out.min.push_back(m.front());
  }
  return out;
}

Camera view(const Scene& scene) {
  const auto [lo, hi] = scene.bounds();
  const Vec3 centre{(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2};
  const double size = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
  return Camera::orbit(centre, 30, 30, 3 * size, 512, 512, 30);
}

}  // namespace

int main(int argc, char** argv) {
  const int runs = argc > 1 ? std::max(1, std::atoi(argv[1])) : 21;
  const int hw = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  const std::filesystem::path scad = fuzzycsg::bench::data_file("scad");
  struct Model {
    const char* name;
    Scene scene;
  };
  std::vector<Model> models;
  models.push_back({"small", parse_openscad_csg(fuzzycsg::bench::kSmallScene, "small")});
  models.push_back({"large", read_openscad_csg(scad / "Old/example001.openscad.csg")});
  models.push_back({"dense", read_openscad_csg(scad / "Basics/logo.openscad.csg")});
  gl::Renderer opencsg(512, 512);
  std::printf("512x512, %d hardware threads, median of %d rounds; OpenCSG 1.5 on %s\n", hw, runs,
              opencsg.description().c_str());
  std::printf(
      "model         triangles | ours: %d threads, 1 thread, %d threads new frame | OpenCSG "
      "Goldfeather: "
      "draw, +read | SCS: draw, +read | ratio ours (%d threads) / faster OpenCSG: +read, draw | "
      "pixels differing\n",
      hw, hw, hw);
  for (const Model& m : models) {
    const Camera cam = view(m.scene);
    Frame frame, fresh;
    std::vector<int> ids;
    opencsg.set_scene(m.scene);
    const Timing timing =
        time_ms(runs, {[&] { render_visibility(m.scene, cam, frame, hw); },
                       [&] { render_visibility(m.scene, cam, frame, 1); },
                       [&] { fresh = render_visibility(m.scene, cam, hw); },
                       [&] { opencsg.draw(cam, gl::Algorithm::kGoldfeather); },
                       [&] { ids = opencsg.render(cam, gl::Algorithm::kGoldfeather); },
                       [&] { opencsg.draw(cam, gl::Algorithm::kScs); },
                       [&] { ids = opencsg.render(cam, gl::Algorithm::kScs); }});
    int differ = 0;
    for (std::size_t px = 0; px < ids.size(); ++px) differ += ids[px] != frame.primitive[px];
    for (const bool median : {true, false}) {
      const std::vector<double>& t = median ? timing.median : timing.min;
      std::printf(
          "%-6s %-6s %9zu | %6.1f ms %6.1f ms %6.1f ms | %6.1f ms %6.1f ms | %6.1f ms %6.1f ms | "
          "%5.2fx %5.2fx | %d of %d\n",
          m.name, median ? "median" : "min", m.scene.triangle_count(), t[0], t[1], t[2], t[3], t[4],
          t[5], t[6], t[0] / std::min(t[4], t[6]), t[0] / std::min(t[3], t[5]), differ,
          frame.visible_pixels());
    }
  }
  return 0;
}
