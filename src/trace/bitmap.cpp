#include "fuzzycsg/trace/bitmap.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <string>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/target/picture.hpp"

namespace fuzzycsg::trace {

Bitmap::Bitmap(int width, int height) {
  if (width < 1 || height < 1 ||
      static_cast<std::int64_t>(width) * static_cast<std::int64_t>(height) > kMaxPixels) {
    throw InputError("bitmap: " + std::to_string(width) + "x" + std::to_string(height) +
                     " pixels is not a valid size (at least 1x1, at most " +
                     std::to_string(kMaxPixels) + " pixels)");
  }
  width_ = width;
  height_ = height;
  words_ = (width + 63) / 64;
  bits_.assign(static_cast<std::size_t>(words_) * static_cast<std::size_t>(height), 0);
}

void Bitmap::set_span(int r, int c0, int c1) {
  if (c0 >= c1) return;
  std::uint64_t* w = row(r);
  const int w0 = c0 >> 6, w1 = (c1 - 1) >> 6;
  const std::uint64_t first = ~std::uint64_t{0} << (c0 & 63);
  const std::uint64_t last = ~std::uint64_t{0} >> (63 - ((c1 - 1) & 63));
  if (w0 == w1) {
    w[w0] |= first & last;
    return;
  }
  w[w0] |= first;
  for (int k = w0 + 1; k < w1; ++k) w[k] = ~std::uint64_t{0};
  w[w1] |= last;
}

void Bitmap::clear_rows(int r0, int r1) {
  r0 = std::max(r0, 0);
  r1 = std::min(r1, height_);
  if (r0 >= r1) return;
  std::fill(bits_.begin() + static_cast<std::ptrdiff_t>(index(r0)),
            bits_.begin() + static_cast<std::ptrdiff_t>(index(r1)), 0);
}

std::int64_t Bitmap::count() const {
  std::int64_t n = 0;
  for (const std::uint64_t w : bits_) n += std::popcount(w);
  return n;
}

Bitmap bitmap_from_bytes(std::span<const std::uint8_t> inside, int width, int height) {
  Bitmap b(width, height);
  if (inside.size() != static_cast<std::size_t>(width) * static_cast<std::size_t>(height)) {
    throw InputError("bitmap: " + std::to_string(inside.size()) + " bytes for " +
                     std::to_string(width) + "x" + std::to_string(height) + " pixels");
  }
  for (int r = 0; r < height; ++r) {
    for (int c = 0; c < width; ++c) {
      if (inside[static_cast<std::size_t>(r) * static_cast<std::size_t>(width) +
                 static_cast<std::size_t>(c)]) {
        b.set(c, r);
      }
    }
  }
  return b;
}

std::vector<std::uint8_t> bitmap_to_bytes(const Bitmap& b) {
  std::vector<std::uint8_t> out(static_cast<std::size_t>(b.width()) *
                                static_cast<std::size_t>(b.height()));
  for (int r = 0; r < b.height(); ++r) {
    for (int c = 0; c < b.width(); ++c) {
      out[static_cast<std::size_t>(r) * static_cast<std::size_t>(b.width()) +
          static_cast<std::size_t>(c)] = b.get(c, r) ? 1 : 0;
    }
  }
  return out;
}

void check_traceable(const Bitmap& bitmap, const std::string& name) {
  const std::int64_t set = bitmap.count();
  const std::int64_t all = std::int64_t{bitmap.width()} * bitmap.height();
  if (set == 0) {
    throw InputError(
        fmt::format("{}: nothing is inside: no dark pixels at {}x{} (inside is "
                    "darker than half grey)",
                    name, bitmap.width(), bitmap.height()));
  }
  if (set == all) {
    throw InputError(
        fmt::format("{}: nothing is outside: no light pixels at {}x{} (outside is "
                    "at least half grey)",
                    name, bitmap.width(), bitmap.height()));
  }
}

Bitmap read_bitmap(const std::filesystem::path& path) {
  const Picture p = read_picture(path, path.string());
  return bitmap_from_bytes(p.inside, p.width, p.height);
}

}  // namespace fuzzycsg::trace
