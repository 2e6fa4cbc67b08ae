// raster_bench: the forward pass of CSG of meshed primitives by rays (diffcsg/visibility.hpp)
// at 512 x 512, with every hardware thread and with one (the baseline, same process), on two
// models:
//   small  a cube less a cylinder of 29 sides, with a bar through it: 136 triangles, near the
//          128 of DiffCSG's Table 1;
//   large  OpenSCAD's example001 (a ball less three cylinders; $fa = 12, $fs = 2): 1,244
//          triangles (Table 1's other model has 2,980).
// Prints milliseconds per frame (median of 5, after one warm-up frame, into a frame reused from
// call to call) and the ratio. The paper's GPU times for a
// forward and backward step (Table 1: 0.061 s for 128 triangles, 0.345 s for 2,980) are
// printed for reference; this is the forward visibility only.
//
//   raster_bench [runs]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <thread>
#include <vector>

#include "bench/bench_lists.hpp"
#include "bench/data_dir.hpp"
#include "diffcsg_scenes.hpp"
#include "fuzzycsg/diffcsg/openscad_csg.hpp"
#include "fuzzycsg/diffcsg/visibility.hpp"

using namespace fuzzycsg::diffcsg;

using fuzzycsg::bench::median;

int main(int argc, char** argv) {
  const int runs = argc > 1 ? std::max(1, std::atoi(argv[1])) : 5;
  const int hw = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  struct Model {
    const char* name;
    Scene scene;
  };
  std::vector<Model> models;
  models.push_back({"small", parse_openscad_csg(fuzzycsg::bench::kSmallScene, "small")});
  models.push_back(
      {"large", read_openscad_csg(fuzzycsg::bench::data_file("scad/Old/example001.openscad.csg"))});
  std::printf("512x512, %d hardware threads, median of %d frames\n", hw, runs);
  for (const Model& m : models) {
    const auto [lo, hi] = m.scene.bounds();
    const Vec3 centre{(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2};
    const double size = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
    const Camera cam = Camera::orbit(centre, 30, 30, 3 * size, 512, 512, 30);
    double times[2] = {0, 0};
    int covered = 0;
    Frame f;  // reused: a new 512 x 512 frame is 8 MB to page in
    for (const int threads : {hw, 1}) {
      std::vector<double> ms;
      render_visibility(m.scene, cam, f, threads);  // warm-up
      for (int r = 0; r < runs; ++r) {
        const auto t0 = std::chrono::steady_clock::now();
        render_visibility(m.scene, cam, f, threads);
        ms.push_back(
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                .count());
        covered = f.visible_pixels();
      }
      times[threads == 1 ? 1 : 0] = median(ms);
    }
    std::printf(
        "%-6s %5zu triangles, %6d pixels covered: %7.1f ms with %d threads, %7.1f ms "
        "with 1 (ratio %.2fx)\n",
        m.name, m.scene.triangle_count(), covered, times[0], hw, times[1], times[1] / times[0]);
  }
  std::printf(
      "paper (Table 1, GPU, forward + backward): 61 ms at 128 triangles, 345 ms at "
      "2,980\n");
  return 0;
}
