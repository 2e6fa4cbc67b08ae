#pragma once
// The larger data collection that benchmarks and studies read (CAD meshes, glyphs, OpenSCAD
// models, the reference cases of Liu et al.). It is not part of the repository: its folder is
// $FUZZYCSG_DATA, or ../shared/data beside the repository root when that is unset. The test
// suite never reads it (tests/data holds what the tests need).
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

namespace fuzzycsg::bench {

inline std::filesystem::path data_dir() {
  if (const char* env = std::getenv("FUZZYCSG_DATA"); env != nullptr && *env != '\0') {
    return env;
  }
  return std::filesystem::path(FUZZYCSG_SOURCE_DIR) / ".." / "shared" / "data";
}

// A file of the collection; when it is missing the program says so in one line and exits 2.
inline std::filesystem::path data_file(const std::string& relative) {
  const std::filesystem::path path = data_dir() / relative;
  if (!std::filesystem::exists(path)) {
    std::fprintf(stderr,
                 "%s: missing; this benchmark reads the data collection at %s "
                 "(set FUZZYCSG_DATA to its folder)\n",
                 path.string().c_str(), data_dir().string().c_str());
    std::exit(2);
  }
  return path;
}

}  // namespace fuzzycsg::bench
