// Pictures read as binary masks: PNG, JPEG and the other formats of stb_image, and Netpbm
// bitmaps and greymaps by a reader of their own.
#include <fmt/format.h>
#include <stb_image.h>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <memory>
#include <string_view>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/target/picture.hpp"
#include "target_detail.hpp"

namespace fuzzycsg {

namespace {

using target_detail::fail;

// The largest picture read (8192^2): decoded grey and alpha, it takes 128 MiB. A few kilobytes
// of PNG can claim far more.
constexpr std::uint64_t kMaxPixels = std::uint64_t{1} << 26;

void check_size(int width, int height, const std::string& name) {
  if (static_cast<std::uint64_t>(width) * static_cast<std::uint64_t>(height) > kMaxPixels) {
    fail(name, fmt::format("cannot read image ({}x{} pixels is too large; at most {} pixels)",
                           width, height, kMaxPixels));
  }
}

struct StbFree {
  void operator()(unsigned char* p) const { stbi_image_free(p); }
};

Picture decode_with_stb(const std::string& bytes, const std::string& name) {
  if (bytes.size() > static_cast<std::size_t>(std::numeric_limits<int>::max())) {
    fail(name, "cannot read image (file too large)");
  }
  int width = 0, height = 0, channels = 0;
  const auto* data_in = reinterpret_cast<const stbi_uc*>(bytes.data());
  const int size = static_cast<int>(bytes.size());
  if (stbi_info_from_memory(data_in, size, &width, &height, &channels)) {
    check_size(width, height, name);
  }
  // Grey and alpha: a transparent background counts as white (icons are often drawn as dark
  // shapes on a transparent background). stb converts to them itself, except from binary PNM
  // (P5, P6, which it reads whatever the file's name): with 16-bit samples its conversion reads
  // past its buffer, so those come in their own channels and are converted below as stb would.
  const bool pnm = bytes.size() >= 2 && bytes[0] == 'P' && (bytes[1] == '5' || bytes[1] == '6');
  std::unique_ptr<unsigned char, StbFree> data(
      stbi_load_from_memory(data_in, size, &width, &height, &channels, pnm ? 0 : 2));
  if (!data) {
    // stb names an unknown PNG chunk by its four bytes, as they are in the file.
    std::string reason = stbi_failure_reason() ? stbi_failure_reason() : "unknown error";
    std::replace_if(
        reason.begin(), reason.end(), [](char c) { return c < 0x20 || c > 0x7e; }, '?');
    fail(name, "cannot read image (" + reason + ")");
  }
  // stb's own answer, which need not be what stbi_info said (or stbi_info may have failed):
  // a PNM header of width or height 0 decodes to an image of no pixels.
  if (width < 1 || height < 1) {
    fail(name, fmt::format("cannot read image (the width and height must be at least 1, got {}x{})",
                           width, height));
  }
  check_size(width, height, name);
  Picture b;
  b.width = width;
  b.height = height;
  b.inside.resize(static_cast<std::size_t>(width) * static_cast<std::size_t>(height));
  const int stride = pnm ? channels : 2;
  if (stride < 1 || stride > 4) fail(name, fmt::format("cannot read image ({} channels)", stride));
  for (std::size_t i = 0; i < b.inside.size(); ++i) {
    const unsigned char* p = data.get() + static_cast<std::size_t>(stride) * i;
    // Luminance as stb computes it (stbi__compute_y); alpha 255 where there is none.
    const int grey = stride >= 3 ? (p[0] * 77 + p[1] * 150 + p[2] * 29) >> 8 : p[0];
    const int alpha = stride == 2 ? p[1] : stride == 4 ? p[3] : 255;
    // Over white: grey * a + 255 * (1 - a), in units of 1/255^2; dark below one half.
    const int value = grey * alpha + 255 * (255 - alpha);
    b.inside[i] = 2 * value < 255 * 255 ? 1 : 0;
  }
  return b;
}

// Netpbm bitmaps (P1 plain, P4 raw) and greymaps (P2 plain, P5 raw). stb_image reads only the
// raw greymaps and pixmaps, not bitmaps nor plain text; one reader for all four keeps them
// consistent.
class PnmReader {
 public:
  PnmReader(std::string_view bytes, const std::string& name) : s_(bytes), name_(name) {}

  Picture read() {
    if (s_.size() < 2 || s_[0] != 'P' || s_[1] < '1' || s_[1] > '6') {
      fail(name_, "cannot read image (not a PBM or PGM file)");
    }
    const char kind = s_[1];
    if (kind == '3' || kind == '6') {
      fail(name_, fmt::format("cannot read image (P{} is a colour pixmap; expected a PBM or PGM "
                              "file: P1, P2, P4 or P5)",
                              kind));
    }
    pos_ = 2;
    const bool bitmap = kind == '1' || kind == '4';
    Picture b;
    b.width = number("width");
    b.height = number("height");
    const int maxval = bitmap ? 1 : number("maximum value");
    if (b.width < 1 || b.height < 1) bad("the width and height must be at least 1");
    if (maxval < 1 || maxval > 65535) bad("the maximum value must be in [1, 65535]");
    check_size(b.width, b.height, name_);
    const auto w = static_cast<std::size_t>(b.width), h = static_cast<std::size_t>(b.height);
    b.inside.resize(w * h);
    if (kind == '4' || kind == '5') {
      // One whitespace character separates the header from the raster.
      if (pos_ >= s_.size() || !is_space(s_[pos_])) bad("no whitespace after the header");
      ++pos_;
    }
    switch (kind) {
      case '1':
        for (auto& v : b.inside) {
          skip_space();
          if (pos_ >= s_.size()) bad("truncated raster");
          if (s_[pos_] != '0' && s_[pos_] != '1') bad("expected 0 or 1 in the raster");
          v = s_[pos_++] == '1' ? 1 : 0;  // 1 is black
        }
        break;
      case '2':
        for (auto& v : b.inside) {
          const int value = number("pixel value");
          if (value > maxval) bad("a sample exceeds the maximum value");
          v = dark(value, maxval);
        }
        break;
      case '4': {
        const std::size_t row = (w + 7) / 8;
        if (s_.size() - pos_ < row * h) bad("truncated raster");
        for (std::size_t y = 0; y < h; ++y) {
          for (std::size_t x = 0; x < w; ++x) {
            const auto byte = static_cast<unsigned char>(s_[pos_ + y * row + x / 8]);
            b.inside[y * w + x] = (byte >> (7 - x % 8)) & 1u;
          }
        }
        break;
      }
      default: {  // '5'
        const std::size_t bytes = maxval < 256 ? 1 : 2;
        if (s_.size() - pos_ < bytes * w * h) bad("truncated raster");
        for (std::size_t i = 0; i < w * h; ++i) {
          const auto* p = reinterpret_cast<const unsigned char*>(s_.data() + pos_ + bytes * i);
          const int value = bytes == 1 ? p[0] : (p[0] << 8) | p[1];  // big-endian
          if (value > maxval) bad("a sample exceeds the maximum value");
          b.inside[i] = dark(value, maxval);
        }
        break;
      }
    }
    return b;
  }

 private:
  static bool is_space(char c) {
    return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
  }
  static std::uint8_t dark(int value, int maxval) { return 2 * value < maxval ? 1 : 0; }

  [[noreturn]] void bad(const std::string& problem) const {
    fail(name_, "cannot read image (" + problem + ")");
  }

  // Whitespace and comments (from '#' to the end of the line).
  void skip_space() {
    while (pos_ < s_.size()) {
      if (s_[pos_] == '#') {
        while (pos_ < s_.size() && s_[pos_] != '\n' && s_[pos_] != '\r') ++pos_;
      } else if (is_space(s_[pos_])) {
        ++pos_;
      } else {
        break;
      }
    }
  }

  // A decimal number; after a header number the reader stays on the whitespace that ends it.
  int number(const char* what) {
    skip_space();
    const std::size_t start = pos_;
    long long v = 0;
    while (pos_ < s_.size() && s_[pos_] >= '0' && s_[pos_] <= '9') {
      v = v * 10 + (s_[pos_] - '0');
      if (v > 1'000'000'000) bad(fmt::format("the {} is too large", what));
      ++pos_;
    }
    if (pos_ == start) bad(pos_ >= s_.size() ? "truncated" : fmt::format("expected the {}", what));
    return static_cast<int>(v);
  }

  std::string_view s_;
  const std::string& name_;
  std::size_t pos_ = 0;
};

}  // namespace

Picture read_picture(const std::filesystem::path& path, const std::string& name) {
  const std::string bytes = target_detail::read_file_bytes(path, name);
  const std::string ext = target_detail::lowercase_extension(path);
  return ext == ".pbm" || ext == ".pgm" ? PnmReader(bytes, name).read()
                                        : decode_with_stb(bytes, name);
}

}  // namespace fuzzycsg
