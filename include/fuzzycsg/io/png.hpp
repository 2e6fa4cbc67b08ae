#pragma once
// PNG encoding through stb_image_write, to memory (the caller writes the bytes atomically).

#include <span>
#include <string>

namespace fuzzycsg {

// PNG bytes of an 8-bit image (channels 1, 3 or 4), rows top to bottom.
std::string encode_png(int width, int height, int channels, std::span<const unsigned char> pixels);

}  // namespace fuzzycsg
