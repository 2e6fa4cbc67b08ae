// A target mesh and a result side by side from the same cameras (render.hpp,
// render_comparison_png): a row of views each, labelled, composed on io's Canvas.

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/io/canvas.hpp"
#include "fuzzycsg/render/render.hpp"
#include "raycast.hpp"

namespace fuzzycsg {

namespace {

constexpr int kMinSide = 16, kMaxSide = 2048, kMaxViews = 8;
constexpr int kGap = 6;       // white pixels between views, and around them
constexpr int kCaption = 24;  // the strip of column captions above the views
constexpr double kLabelSize = 16, kCaptionSize = 13;
constexpr Rgb kInk{40, 40, 40}, kPaleInk{110, 110, 110};
constexpr const char* kEmpty = "(empty)";

void check_options(const ComparisonOptions& o) {
  if (o.width < kMinSide || o.width > kMaxSide || o.height < kMinSide || o.height > kMaxSide) {
    throw OptionError("width, height", fmt::format("must be {}..{} pixels each (got {}x{})",
                                                   kMinSide, kMaxSide, o.width, o.height));
  }
  if (o.views.empty() || o.views.size() > static_cast<std::size_t>(kMaxViews)) {
    throw OptionError("views", fmt::format("must be 1..{} (got {})", kMaxViews, o.views.size()));
  }
  if (!(o.crease_deg > 0 && o.crease_deg <= 180)) {
    throw OptionError("crease_deg",
                      fmt::format("must be in (0, 180] degrees (got {})", o.crease_deg));
  }
  for (const ComparisonView& v : o.views) {
    if (!std::isfinite(v.azimuth_deg) || !(v.elevation_deg > -90 && v.elevation_deg < 90)) {
      throw OptionError("views", fmt::format("elevation must be in (-90, 90) degrees and azimuth "
                                             "finite (got azimuth {:g}, elevation {:g})",
                                             v.azimuth_deg, v.elevation_deg));
    }
  }
}

// The box around both meshes' vertices (the target's alone when the result has none).
std::array<std::array<double, 3>, 2> union_box(const TriangleMesh& a, const TriangleMesh& b) {
  auto box = bounding_box(a);
  if (b.triangles.empty()) return box;
  const auto other = bounding_box(b);
  for (std::size_t k = 0; k < 3; ++k) {
    box[0][k] = std::min(box[0][k], other[0][k]);
    box[1][k] = std::max(box[1][k], other[1][k]);
  }
  return box;
}

// The mesh from each camera, as pixels.
std::vector<Pixels> views_of(const TriangleMesh& mesh, const std::vector<Camera>& cameras,
                             int width, int height, double crease_deg) {
  const render_detail::MeshShader shader(mesh, crease_deg);
  std::vector<unsigned char> rgb(static_cast<std::size_t>(width) * height * 3);
  std::vector<Pixels> views;
  for (const Camera& c : cameras) {
    shader.shade(c, width, height, rgb.data(), static_cast<std::size_t>(width) * 3);
    Pixels& p = views.emplace_back(width, height);
    for (int y = 0; y < height; ++y) {
      for (int x = 0; x < width; ++x) {
        const unsigned char* q = rgb.data() + (static_cast<std::size_t>(y) * width + x) * 3;
        p.at(x, y) = Rgb{q[0], q[1], q[2]};
      }
    }
  }
  return views;
}

std::string compose(const TriangleMesh& target, const TriangleMesh& result,
                    const ComparisonOptions& o) {
  const int w = o.width, h = o.height, n = static_cast<int>(o.views.size());
  const double aspect = static_cast<double>(w) / h;
  std::vector<Camera> cameras;
  const auto box = union_box(target, result);
  for (const ComparisonView& v : o.views) {
    cameras.push_back(framing_camera(box, v.azimuth_deg, v.elevation_deg, o.up, aspect));
    // A framing camera's eye is outside the sphere around both shapes, hence outside both.
    render_detail::check_camera_geometry(cameras.back());
  }
  const std::vector<Pixels> rows[2] = {views_of(target, cameras, w, h, o.crease_deg),
                                       result.triangles.empty()
                                           ? std::vector<Pixels>{}
                                           : views_of(result, cameras, w, h, o.crease_deg)};

  const double label_width = std::max({Canvas::text_width(o.target_label, kLabelSize),
                                       Canvas::text_width(o.result_label, kLabelSize),
                                       Canvas::text_width(kEmpty, kCaptionSize)});
  const int left = kGap + static_cast<int>(std::ceil(label_width)) + 2 * kGap;
  Canvas canvas(left + n * w + n * kGap, kCaption + 2 * h + 2 * kGap);
  const auto x_of = [&](int column) { return left + column * (w + kGap); };
  const auto y_of = [&](int row) { return kCaption + row * (h + kGap); };
  for (int k = 0; k < n; ++k) {
    const ComparisonView& v = o.views[static_cast<std::size_t>(k)];
    std::string caption =
        fmt::format("azimuth {:g}\u00b0, elevation {:g}\u00b0", v.azimuth_deg, v.elevation_deg);
    if (Canvas::text_width(caption, kCaptionSize) > w - 4) {
      caption = fmt::format("{:g}\u00b0, {:g}\u00b0", v.azimuth_deg, v.elevation_deg);
    }
    canvas.text(x_of(k) + 0.5 * w, 0.5 * kCaption, caption, kPaleInk, kCaptionSize, Align::kCentre,
                Anchor::kMiddle);
  }
  const std::string* labels[2] = {&o.target_label, &o.result_label};
  for (int r = 0; r < 2; ++r) {
    const double middle = y_of(r) + 0.5 * h;
    canvas.text(kGap, middle, *labels[r], kInk, kLabelSize, Align::kLeft, Anchor::kMiddle);
    if (rows[r].empty()) {
      canvas.text(kGap, middle + 1.4 * kLabelSize, kEmpty, kPaleInk, kCaptionSize, Align::kLeft,
                  Anchor::kMiddle);
      continue;
    }
    for (int k = 0; k < n; ++k) {
      canvas.image(x_of(k), y_of(r), rows[r][static_cast<std::size_t>(k)]);
    }
  }
  return canvas.png();
}

}  // namespace

std::string render_comparison_png(const TriangleMesh& target, const TriangleMesh& result,
                                  const ComparisonOptions& o) {
  check_options(o);
  if (target.triangles.empty()) throw InputError("render: the target mesh has no triangles");
  return render_detail::in_arena(o.threads, [&] { return compose(target, result, o); });
}

std::string render_comparison_png(const TriangleMesh& target, const Tree& tree,
                                  std::span<const double> params, const ComparisonOptions& o) {
  if (tree.dim != 3) throw InputError("render: the tree is 2D (its picture is drawn by plot)");
  check_options(o);
  if (target.triangles.empty()) throw InputError("render: the target mesh has no triangles");
  return render_detail::in_arena(o.threads, [&] {
    MeshOptions mo;
    mo.resolution = o.resolution;
    mo.threads = o.threads;
    return compose(target, extract_mesh(tree, params, mo), o);
  });
}

}  // namespace fuzzycsg
