#pragma once
// Shared by the render tests: PNG bytes decoded (stb_image) to RGB pixels.

#include <stb_image.h>

#include <array>
#include <cstddef>
#include <string>
#include <vector>

namespace fuzzycsg::testing {

struct Image {
  int width = 0, height = 0;
  std::vector<unsigned char> rgb;
  std::array<int, 3> at(int x, int y) const {
    const unsigned char* p = rgb.data() + (static_cast<std::size_t>(y) * width + x) * 3;
    return {p[0], p[1], p[2]};
  }
};

// An empty image (0 x 0) when the bytes are not a picture.
inline Image decode(const std::string& png) {
  Image im;
  int channels = 0;
  unsigned char* data =
      stbi_load_from_memory(reinterpret_cast<const unsigned char*>(png.data()),
                            static_cast<int>(png.size()), &im.width, &im.height, &channels, 3);
  if (data == nullptr) return im;
  im.rgb.assign(data, data + static_cast<std::size_t>(im.width) * im.height * 3);
  stbi_image_free(data);
  return im;
}

}  // namespace fuzzycsg::testing
