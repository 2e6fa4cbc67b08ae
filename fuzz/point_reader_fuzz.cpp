// libFuzzer target: the first byte chooses the number of coordinates (0 to 4; 0 is refused),
// the rest is read as a point file. InputError with one line is the expected answer to bad
// input; any other exception, a crash or a sanitizer report is a bug. Points that read are
// whole points of finite coordinates within the range of float.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "fuzz_support.hpp"
#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/io/points.hpp"

namespace {
constexpr const char* kTarget = "point_reader_fuzz";
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace fuzzycsg;
  if (size < 1) return 0;
  const int dim = data[0] % 5;
  const std::string_view text(reinterpret_cast<const char*>(data + 1), size - 1);
  std::vector<float> points;
  try {
    points = io::read_points_string(text, dim, "fuzz.xyz");
  } catch (const InputError& e) {
    fuzz::check_message(kTarget, e);
    const std::string_view message = e.what();
    if (message.rfind("fuzz.xyz: ", 0) != 0) {
      fuzz::bug(kTarget, "an InputError message does not name the file", message);
    }
    return 0;
  }
  if (dim < 1) fuzz::bug(kTarget, "points of " + std::to_string(dim) + " coordinates were read");
  if (points.empty() || points.size() % static_cast<std::size_t>(dim) != 0) {
    fuzz::bug(
        kTarget,
        std::to_string(points.size()) + " coordinates read for points of " + std::to_string(dim),
        text);
  }
  // One point per line that is neither blank nor a comment.
  std::size_t lines = 0;
  for (std::size_t start = 0; start <= text.size();) {
    std::size_t end = text.find('\n', start);
    if (end == std::string_view::npos) end = text.size();
    const std::string_view line = text.substr(start, end - start);
    const std::size_t first = line.find_first_not_of(" \t\r\v\f");
    if (first != std::string_view::npos && line[first] != '#') ++lines;
    start = end + 1;
  }
  if (points.size() != lines * static_cast<std::size_t>(dim)) {
    fuzz::bug(kTarget,
              std::to_string(points.size()) + " coordinates read from " + std::to_string(lines) +
                  " lines of points",
              text);
  }
  for (const float v : points) {
    if (!std::isfinite(v)) fuzz::bug(kTarget, "a coordinate that is not finite was read", text);
  }
  return 0;
}
