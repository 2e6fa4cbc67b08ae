// libFuzzer target: the first byte chooses the file's extension (.pbm, .pgm, .png; Netpbm goes to
// our own reader by its first bytes, anything else to stb_image) and the image target's grid, the
// rest is written to a file of that extension and read as a picture (read_picture), as a bitmap
// (trace::read_bitmap) and as an image target (resampling, signed distance field, boundary).
// InputError with one line is the expected answer to bad input; any other exception, a crash or
// a sanitizer report is a bug. A picture that reads has a size within the limit and one 0 or 1
// per pixel, and the bitmap reader agrees with it; a target that loads answers occupancy with 0
// or 1 and samples finite boundary points
// in [-1, 1]^2.
//
// stb_image decodes every other format (a Debian shared library, not instrumented): a finding
// whose stack lies inside libstb is stb's.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "fuzz_support.hpp"
#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/target/picture.hpp"
#include "fuzzycsg/target/target.hpp"
#include "fuzzycsg/trace/bitmap.hpp"

namespace {

constexpr const char* kTarget = "picture_loader_fuzz";
using fuzzycsg::fuzz::bug;

void check_picture(const fuzzycsg::Picture& p) {
  if (p.width < 1 || p.height < 1) bug(kTarget, "a picture of no pixels was read");
  const auto pixels = static_cast<std::uint64_t>(p.width) * static_cast<std::uint64_t>(p.height);
  if (pixels > (std::uint64_t{1} << 26)) bug(kTarget, "a picture over the size limit was read");
  if (p.inside.size() != pixels) bug(kTarget, "a picture's pixels do not match its size");
  for (const std::uint8_t v : p.inside) {
    if (v > 1) bug(kTarget, "a pixel that is not 0 or 1");
  }
}

void check_target(const fuzzycsg::Target& target) {
  if (target.dim() != 2 || target.kind() != "image") bug(kTarget, "an image target not 2D");
  const std::vector<float> points = {0, 0, 0.5f, -0.5f, -1, 1, 0.99f, 0.01f, 2, 0};
  fuzzycsg::fuzz::check_crisp_target(kTarget, target, points, 1.0f);
  fuzzycsg::Rng rng(2);
  std::vector<float> weighted;
  target.sample_distance_weighted(16, rng, weighted);
  for (const float x : weighted) {
    if (!(std::abs(x) <= 1.0f)) bug(kTarget, "a weighted sample outside [-1, 1]^2");
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace fuzzycsg;
  static const fuzz::ScratchDir scratch(kTarget);
  if (size < 1) return 0;
  static constexpr std::array<const char*, 3> kNames = {"p.pbm", "p.pgm", "p.png"};
  const std::string_view bytes(reinterpret_cast<const char*>(data + 1), size - 1);
  const std::filesystem::path path = scratch.write(kNames[data[0] % kNames.size()], bytes);
  // The target's grid: 0 (the picture's own size, when small) or 8 to 71 pixels.
  const int selector = data[0] / 3 % 65;
  const int resolution = selector == 0 ? 0 : selector + 7;

  Picture picture;
  try {
    picture = read_picture(path, "fuzz");
  } catch (const InputError& e) {
    fuzz::check_message(kTarget, e);
    try {
      trace::read_bitmap(path);
    } catch (const InputError& again) {
      fuzz::check_message(kTarget, again);
      return 0;
    }
    bug(kTarget, std::string("read_bitmap read what read_picture refused: ") + e.what());
  }
  check_picture(picture);
  trace::Bitmap bitmap;
  try {
    bitmap = trace::read_bitmap(path);
  } catch (const InputError& e) {
    bug(kTarget, std::string("read_bitmap refused what read_picture read: ") + e.what());
  }
  if (bitmap.width() != picture.width || bitmap.height() != picture.height ||
      trace::bitmap_to_bytes(bitmap) != picture.inside) {
    bug(kTarget, "read_bitmap and read_picture disagree");
  }

  if (resolution == 0 && std::max(picture.width, picture.height) > 256) return 0;
  TargetOptions options;
  options.threads = 1;
  options.image_resolution = resolution;
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
