// Pictures read as binary masks: PNG, JPEG and the other formats of stb_image, and Netpbm
// (bitmaps, greymaps and pixmaps) by a reader of their own.
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
  // shapes on a transparent background). Netpbm never comes here (read_picture).
  std::unique_ptr<unsigned char, StbFree> data(
      stbi_load_from_memory(data_in, size, &width, &height, &channels, 2));
  if (!data) {
    // stb names an unknown PNG chunk by its four bytes, as they are in the file.
    std::string reason = stbi_failure_reason() ? stbi_failure_reason() : "unknown error";
    std::replace_if(
        reason.begin(), reason.end(), [](char c) { return c < 0x20 || c > 0x7e; }, '?');
    fail(name, "cannot read image (" + reason + ")");
  }
  // stb's own answer, which need not be what stbi_info said (or stbi_info may have failed).
  if (width < 1 || height < 1) {
    fail(name, fmt::format("cannot read image (the width and height must be at least 1, got {}x{})",
                           width, height));
  }
  check_size(width, height, name);
  Picture b;
  b.width = width;
  b.height = height;
  b.inside.resize(static_cast<std::size_t>(width) * static_cast<std::size_t>(height));
  for (std::size_t i = 0; i < b.inside.size(); ++i) {
    const unsigned char* p = data.get() + 2 * i;
    const int grey = p[0];
    const int alpha = p[1];
    // Over white: grey * a + 255 * (1 - a), in units of 1/255^2; dark below one half.
    const int value = grey * alpha + 255 * (255 - alpha);
    b.inside[i] = 2 * value < 255 * 255 ? 1 : 0;
  }
  return b;
}

// Netpbm: bitmaps (P1 plain, P4 raw), greymaps (P2, P5) and pixmaps (P3, P6). stb_image reads
// only the raw greymaps and pixmaps, not bitmaps nor plain text, and leaves the pixels of a
// truncated raster undefined; one reader for all six keeps them consistent.
class PnmReader {
 public:
  PnmReader(std::string_view bytes, const std::string& name) : s_(bytes), name_(name) {}

  // Whether bytes begin as a Netpbm file ("P1" to "P6"), whatever the file's name.
  static bool recognises(std::string_view bytes) {
    return bytes.size() >= 2 && bytes[0] == 'P' && bytes[1] >= '1' && bytes[1] <= '6';
  }

  Picture read() {
    if (!recognises(s_)) fail(name_, "cannot read image (not a Netpbm file: P1 to P6)");
    const char kind = s_[1];
    pos_ = 2;
    const bool bitmap = kind == '1' || kind == '4';
    Picture b;
    b.width = number("width");
    b.height = number("height");
    const int maxval = bitmap ? 1 : number("maximum value");
    if (b.width < 1 || b.height < 1) {
      bad(fmt::format("the width and height must be at least 1, got {}x{}", b.width, b.height));
    }
    if (maxval < 1 || maxval > 65535) bad("the maximum value must be in [1, 65535]");
    check_size(b.width, b.height, name_);
    b.inside.resize(static_cast<std::size_t>(b.width) * static_cast<std::size_t>(b.height));
    if (kind >= '4') {
      // One whitespace character separates the header from the raster.
      if (pos_ >= s_.size() || !is_space(s_[pos_])) bad("no whitespace after the header");
      ++pos_;
    }
    switch (kind) {
      case '1':
        read_plain_bits(b);
        break;
      case '4':
        read_raw_bits(b);
        break;
      default:
        read_samples(b, kind == '3' || kind == '6' ? 3 : 1, kind >= '4', maxval);
        break;
    }
    return b;
  }

 private:
  void read_plain_bits(Picture& b) {
    for (auto& v : b.inside) {
      skip_space();
      if (pos_ >= s_.size()) bad("truncated raster");
      if (s_[pos_] != '0' && s_[pos_] != '1') bad("expected 0 or 1 in the raster");
      v = s_[pos_++] == '1' ? 1 : 0;  // 1 is black
    }
  }

  void read_raw_bits(Picture& b) const {
    const auto w = static_cast<std::size_t>(b.width), h = static_cast<std::size_t>(b.height);
    const std::size_t row = (w + 7) / 8;
    if (s_.size() - pos_ < row * h) bad("truncated raster");
    for (std::size_t y = 0; y < h; ++y) {
      for (std::size_t x = 0; x < w; ++x) {
        const auto byte = static_cast<unsigned char>(s_[pos_ + y * row + x / 8]);
        b.inside[y * w + x] = (byte >> (7 - x % 8)) & 1u;
      }
    }
  }

  // Grey (one sample a pixel) or colour (three), as text or raw (big-endian when maxval > 255).
  // Colour becomes its luminance as stb_image computes it (stbi__compute_y).
  void read_samples(Picture& b, int samples, bool raw, int maxval) {
    const std::size_t bytes = maxval < 256 ? 1 : 2;
    if (raw && (s_.size() - pos_) / bytes / static_cast<std::size_t>(samples) < b.inside.size()) {
      bad("truncated raster");
    }
    const auto sample = [&] {
      int value = 0;
      if (raw) {
        const auto* p = reinterpret_cast<const unsigned char*>(s_.data() + pos_);
        value = bytes == 1 ? p[0] : (p[0] << 8) | p[1];
        pos_ += bytes;
      } else {
        value = number("pixel value");
      }
      if (value > maxval) bad("a sample exceeds the maximum value");
      return value;
    };
    for (auto& v : b.inside) {
      int grey = sample();
      if (samples == 3) {
        const int green = sample(), blue = sample();
        grey = (grey * 77 + green * 150 + blue * 29) >> 8;
      }
      v = dark(grey, maxval);
    }
  }

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
  // Netpbm by its first bytes, whatever the name; a .pbm or .pgm that is not one says so.
  return PnmReader::recognises(bytes) || ext == ".pbm" || ext == ".pgm"
             ? PnmReader(bytes, name).read()
             : decode_with_stb(bytes, name);
}

}  // namespace fuzzycsg
