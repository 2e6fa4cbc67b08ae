#pragma once
// Pictures read as binary masks, as the image target and the bitmap tracer read them.
//
// .pbm and .pgm files (Netpbm P1, P2, P4, P5) are read by a reader of their own; every other
// file goes to stb_image (PNG, JPEG, BMP, GIF, TGA, PSD, HDR, PIC, raw PGM/PPM). Colour is
// reduced to luminance, a transparent pixel is composited over white, and a pixel is inside
// (dark) when its value is below one half. Pictures of more than 2^26 pixels (8192^2) are
// refused before they are decoded.

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace fuzzycsg {

// inside[row * width + col] (1: inside), row 0 at the top.
struct Picture {
  int width = 0, height = 0;
  std::vector<std::uint8_t> inside;
};

// `name` is the file as messages name it. Throws InputError, one line: "NAME: cannot read image
// (reason)" (also for a missing or empty file: "NAME: cannot read (reason)", "NAME: empty file").
Picture read_picture(const std::filesystem::path& path, const std::string& name);

}  // namespace fuzzycsg
