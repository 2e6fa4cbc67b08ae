#pragma once
// Binary pictures for the bitmap tracer (Gibson et al. 1997): W x H bits, each row packed into
// 64-bit words (bit c % 64 of word c / 64 is column c), so that the boolean operators of a CSG
// tree and the EXCESS / UNCOVERED counts run a word (64 pixels) at a time.
//
// Pixel coordinates: column i (from the left) and row j (from the top) is the unit square
// [i, i + 1] x [j, j + 1], its centre at (i + 1/2, j + 1/2); y grows downwards.

#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

namespace fuzzycsg::trace {

class Bitmap {
 public:
  // The largest picture (8192^2 pixels, 8 MiB of bits).
  static constexpr std::int64_t kMaxPixels = std::int64_t{1} << 26;

  Bitmap() = default;
  // All pixels clear. Throws InputError unless width, height >= 1 and width * height <=
  // kMaxPixels.
  Bitmap(int width, int height);

  int width() const { return width_; }
  int height() const { return height_; }
  int words_per_row() const { return words_; }
  bool empty() const { return width_ == 0; }

  bool get(int col, int row) const {
    return (bits_[index(row) + static_cast<std::size_t>(col >> 6)] >> (col & 63)) & 1u;
  }
  void set(int col, int row, bool value = true) {
    std::uint64_t& w = bits_[index(row) + static_cast<std::size_t>(col >> 6)];
    const std::uint64_t b = std::uint64_t{1} << (col & 63);
    w = value ? (w | b) : (w & ~b);
  }
  // Sets columns [c0, c1) of `row` (0 <= c0 <= c1 <= width).
  void set_span(int row, int c0, int c1);
  void clear_rows(int r0, int r1);  // rows [r0, r1)
  void clear() { std::fill(bits_.begin(), bits_.end(), 0); }

  std::uint64_t* row(int r) { return bits_.data() + index(r); }
  const std::uint64_t* row(int r) const { return bits_.data() + index(r); }
  std::span<const std::uint64_t> words() const { return bits_; }
  std::span<std::uint64_t> words() { return bits_; }

  // Number of set pixels (bits past the width are always clear).
  std::int64_t count() const;

  friend bool operator==(const Bitmap&, const Bitmap&) = default;

 private:
  std::size_t index(int row) const {
    return static_cast<std::size_t>(row) * static_cast<std::size_t>(words_);
  }
  int width_ = 0, height_ = 0, words_ = 0;
  std::vector<std::uint64_t> bits_;
};

// A picture file as a bitmap: PNG, JPEG, ... (stb_image) and Netpbm P1 to P6, read as
// fuzzycsg/target/picture.hpp reads them (luminance, alpha over white, dark below one half is
// set). Throws InputError with one line naming the file for unreadable, corrupt or too large
// pictures (more than 8192^2 pixels).
Bitmap read_bitmap(const std::filesystem::path& path);

// A picture worth tracing has a set (dark) pixel and a clear (light) one, as `fit` asks of its
// pictures; InputError "NAME: nothing is inside: ..." or "NAME: nothing is outside: ..."
// otherwise (so also for a 1x1 picture). search() itself accepts such bitmaps.
void check_traceable(const Bitmap& bitmap, const std::string& name);

// From one byte per pixel (non-zero: set), row-major, row 0 at the top.
Bitmap bitmap_from_bytes(std::span<const std::uint8_t> inside, int width, int height);
std::vector<std::uint8_t> bitmap_to_bytes(const Bitmap& b);

}  // namespace fuzzycsg::trace
