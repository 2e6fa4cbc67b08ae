// Pictures read back (stb_image) and scaled down, for contact sheets of the program's outputs.

#include <fmt/format.h>
#include <stb_image.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/io/canvas.hpp"

namespace fuzzycsg {

Pixels decode_picture(std::string_view bytes, const std::string& name) {
  int w = 0, h = 0, channels = 0;
  const std::unique_ptr<unsigned char, void (*)(void*)> data(
      stbi_load_from_memory(reinterpret_cast<const unsigned char*>(bytes.data()),
                            static_cast<int>(std::min<std::size_t>(bytes.size(), INT32_MAX)), &w,
                            &h, &channels, 4),
      stbi_image_free);
  if (!data) {
    throw InputError(fmt::format("{}: not a picture ({})", name, stbi_failure_reason()));
  }
  Pixels p(w, h);
  const unsigned char* px = data.get();
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x, px += 4) {
      const int a = px[3];
      const auto over_white = [a](int c) {
        return static_cast<unsigned char>((c * a + 255 * (255 - a) + 127) / 255);
      };
      p.at(x, y) = {over_white(px[0]), over_white(px[1]), over_white(px[2])};
    }
  }
  return p;
}

Pixels resized(const Pixels& p, int width, int height) {
  Pixels out(width, height);
  const double sx = static_cast<double>(p.width()) / width;
  const double sy = static_cast<double>(p.height()) / height;
  for (int y = 0; y < height; ++y) {
    const double y0 = y * sy, y1 = (y + 1) * sy;
    for (int x = 0; x < width; ++x) {
      const double x0 = x * sx, x1 = (x + 1) * sx;
      double r = 0, g = 0, b = 0, area = 0;
      for (int j = static_cast<int>(y0); j < std::min<int>(p.height(), std::ceil(y1)); ++j) {
        const double wy = std::min<double>(j + 1, y1) - std::max<double>(j, y0);
        for (int i = static_cast<int>(x0); i < std::min<int>(p.width(), std::ceil(x1)); ++i) {
          const double wgt = wy * (std::min<double>(i + 1, x1) - std::max<double>(i, x0));
          const Rgb c = p.at(i, j);
          r += wgt * c.r;
          g += wgt * c.g;
          b += wgt * c.b;
          area += wgt;
        }
      }
      const auto byte = [area](double v) {
        return static_cast<unsigned char>(std::clamp(std::lround(v / area), 0L, 255L));
      };
      out.at(x, y) = {byte(r), byte(g), byte(b)};
    }
  }
  return out;
}

}  // namespace fuzzycsg
