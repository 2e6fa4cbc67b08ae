// fuzzycsg_gallery: draws the modeling gallery (docs/gallery) -- every picture from the trees
// and operators of the library. scripts/make-gallery.sh builds and runs it.
#include <fmt/core.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <exception>
#include <string>
#include <vector>

#include "gallery/figures.hpp"

int main(int argc, char** argv) {
  CLI::App app{"fuzzycsg_gallery: the modeling gallery's pictures", "fuzzycsg_gallery"};
  fuzzycsg::gallery::FigureOptions options;
  std::string out = "docs/gallery";
  std::vector<std::string> only;
  app.add_option("-o,--out", out, "output folder (PNGs, and the trees they draw in trees/)");
  app.add_flag("--quick", options.quick, "small pictures (a smoke test)");
  app.add_option("--only", only, "figures to draw (default: all)");
  CLI11_PARSE(app, argc, argv);
  options.out_dir = out;
  const std::vector<std::string> names = only.empty() ? fuzzycsg::gallery::figure_names() : only;
  try {
    for (const std::string& name : names) {
      const auto t0 = std::chrono::steady_clock::now();
      fuzzycsg::gallery::make_figure(name, options);
      fmt::print("{:<14} {:6.2f} s\n", name,
                 std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
  } catch (const std::exception& e) {
    fmt::print(stderr, "fuzzycsg_gallery: error: {}\n", e.what());
    return 1;
  }
  return 0;
}
