#include "fuzzycsg/io/png.hpp"

#include <stb_image_write.h>

#include "fuzzycsg/core/error.hpp"

namespace fuzzycsg {

namespace {

void append_bytes(void* context, void* data, int size) {
  static_cast<std::string*>(context)->append(static_cast<const char*>(data),
                                             static_cast<std::size_t>(size));
}

}  // namespace

std::string encode_png(int width, int height, int channels, std::span<const unsigned char> pixels) {
  if (width <= 0 || height <= 0 || channels < 1 || channels > 4 ||
      pixels.size() != static_cast<std::size_t>(width) * static_cast<std::size_t>(height) *
                           static_cast<std::size_t>(channels)) {
    throw Error("encode_png: pixel buffer does not match the image size");
  }
  std::string out;
  if (stbi_write_png_to_func(append_bytes, &out, width, height, channels, pixels.data(),
                             width * channels) == 0) {
    throw Error("encode_png: stb_image_write failed");
  }
  return out;
}

}  // namespace fuzzycsg
