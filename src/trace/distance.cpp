#include "distance.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "fuzzycsg/target/signed_distance_grid.hpp"

namespace fuzzycsg::trace {

DistanceMap distance_map(const Bitmap& b) {
  const int w = b.width(), h = b.height();
  DistanceMap d;
  d.width = w;
  d.height = h;
  // Inside: to the nearest clear centre, with a frame of clear pixels around the picture.
  const int pw = w + 2, ph = h + 2;
  std::vector<std::uint8_t> framed(static_cast<std::size_t>(pw) * static_cast<std::size_t>(ph), 0);
  std::vector<std::uint8_t> plain(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), 0);
  for (int r = 0; r < h; ++r) {
    for (int c = 0; c < w; ++c) {
      const std::uint8_t v = b.get(c, r) ? 1 : 0;
      framed[static_cast<std::size_t>(r + 1) * static_cast<std::size_t>(pw) +
             static_cast<std::size_t>(c + 1)] = v;
      plain[d.index(c, r)] = v;
    }
  }
  const std::vector<double> to_clear = squared_distance_transform(framed, pw, ph, 0);
  const std::vector<double> to_set = squared_distance_transform(plain, w, h, 1);
  d.inside.assign(plain.size(), 0.0);
  d.outside.assign(plain.size(), 0.0);
  for (int r = 0; r < h; ++r) {
    for (int c = 0; c < w; ++c) {
      const std::size_t i = d.index(c, r);
      if (plain[i]) {
        d.inside[i] =
            std::sqrt(to_clear[static_cast<std::size_t>(r + 1) * static_cast<std::size_t>(pw) +
                               static_cast<std::size_t>(c + 1)]);
      } else {
        d.outside[i] = std::sqrt(to_set[i]);  // infinity stays infinity
      }
    }
  }
  return d;
}

std::vector<Extremum> local_maxima(const std::vector<double>& map, int width, int height) {
  std::vector<Extremum> out;
  const auto at = [&](int c, int r) {
    return map[static_cast<std::size_t>(r) * static_cast<std::size_t>(width) +
               static_cast<std::size_t>(c)];
  };
  for (int r = 0; r < height; ++r) {
    for (int c = 0; c < width; ++c) {
      const double v = at(c, r);
      if (!(v > 0) || !std::isfinite(v)) continue;
      bool peak = true;
      for (int dr = -1; dr <= 1 && peak; ++dr) {
        for (int dc = -1; dc <= 1; ++dc) {
          const int nc = c + dc, nr = r + dr;
          if ((dc == 0 && dr == 0) || nc < 0 || nr < 0 || nc >= width || nr >= height) continue;
          if (at(nc, nr) > v) {
            peak = false;
            break;
          }
        }
      }
      if (peak) out.push_back({c, r, v});
    }
  }
  std::stable_sort(out.begin(), out.end(),
                   [](const Extremum& a, const Extremum& b) { return a.distance > b.distance; });
  return out;
}

Extrema distance_extrema(const DistanceMap& d) {
  return {local_maxima(d.inside, d.width, d.height), local_maxima(d.outside, d.width, d.height)};
}

}  // namespace fuzzycsg::trace
