#include "fuzzycsg/render/render.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/eval/evaluator.hpp"
#include "fuzzycsg/io/png.hpp"
#include "raycast.hpp"

namespace fuzzycsg {

namespace {

using render_detail::add;
using render_detail::cross;
using render_detail::dot;
using render_detail::kPi;
using render_detail::MeshShader;
using render_detail::norm;
using render_detail::normalized;
using render_detail::scale;
using render_detail::sub;
using render_detail::Vec;

void check_camera(const Camera& c, const Tree& tree, std::span<const double> params) {
  render_detail::check_camera_geometry(c);
  const double eye[3] = {c.eye[0], c.eye[1], c.eye[2]};
  if (reference_occupancy(tree, params, eye) >= 0.5) {
    throw InputError(fmt::format("camera: the eye ({:g}, {:g}, {:g}) is inside the shape", c.eye[0],
                                 c.eye[1], c.eye[2]));
  }
}

void check_sizes(const RenderOptions& o) {
  if (o.width < 1 || o.width > 8192 || o.height < 1 || o.height > 8192) {
    throw InputError(
        fmt::format("size must be 1..8192 pixels a side (got {}x{})", o.width, o.height));
  }
  if (o.views < 1 || o.views > 8) {
    throw InputError(fmt::format("views must be 1..8 (got {})", o.views));
  }
  if (!(o.crease_deg > 0 && o.crease_deg <= 180)) {
    throw InputError(
        fmt::format("crease angle must be in (0, 180] degrees (got {})", o.crease_deg));
  }
}

// The given camera, or o.views default cameras around the mesh.
std::vector<Camera> cameras_of(const TriangleMesh& mesh, const RenderOptions& o) {
  if (o.camera) return {*o.camera};
  const double aspect = static_cast<double>(o.width) / o.height;
  std::vector<Camera> cameras;
  for (int k = 0; k < o.views; ++k) {
    cameras.push_back(framing_camera(mesh, -55.0 + 360.0 * k / o.views, 25.0, o.up, aspect));
  }
  return cameras;
}

// The views side by side, one PNG.
std::string shade_views(const TriangleMesh& mesh, const std::vector<Camera>& cameras,
                        const RenderOptions& o) {
  const MeshShader shader(mesh, o.crease_deg);
  const int total_width = o.width * static_cast<int>(cameras.size());
  std::vector<unsigned char> px(static_cast<std::size_t>(total_width) * o.height * 3);
  for (std::size_t k = 0; k < cameras.size(); ++k) {
    shader.shade(cameras[k], o.width, o.height,
                 px.data() + k * static_cast<std::size_t>(o.width) * 3,
                 static_cast<std::size_t>(total_width) * 3);
  }
  return encode_png(total_width, o.height, 3, px);
}

}  // namespace

Camera framing_camera(const TriangleMesh& mesh, double azimuth_deg, double elevation_deg,
                      const std::array<double, 3>& up, double aspect, double fov_deg) {
  return framing_camera(bounding_box(mesh), azimuth_deg, elevation_deg, up, aspect, fov_deg);
}

Camera framing_camera(const std::array<std::array<double, 3>, 2>& box, double azimuth_deg,
                      double elevation_deg, const std::array<double, 3>& up, double aspect,
                      double fov_deg) {
  const auto& [lo, hi] = box;
  const Vec centre = scale(add(lo, hi), 0.5);
  const double radius = std::max(1e-6, 0.5 * norm(sub(hi, lo)));
  // A frame about `up`: e1, e2 horizontal.
  const Vec z = normalized(up);
  Vec e1 = std::abs(z[0]) < 0.9 ? Vec{1, 0, 0} : Vec{0, 1, 0};
  e1 = normalized(sub(e1, scale(z, dot(e1, z))));
  const Vec e2 = cross(z, e1);
  const double az = azimuth_deg * kPi / 180.0, el = elevation_deg * kPi / 180.0;
  const Vec dir =
      add(add(scale(e1, std::cos(el) * std::cos(az)), scale(e2, std::cos(el) * std::sin(az))),
          scale(z, std::sin(el)));
  const double half_v = 0.5 * fov_deg * kPi / 180.0;
  const double half_h = std::atan(std::tan(half_v) * aspect);
  const double distance = 1.08 * radius / std::sin(std::min(half_v, half_h));
  Camera c;
  c.target = centre;
  c.eye = add(centre, scale(dir, distance));
  c.up = z;
  c.fov_deg = fov_deg;
  return c;
}

std::string render_png(const Tree& tree, std::span<const double> params, const RenderOptions& o) {
  if (tree.dim != 3) throw InputError("render: the tree is 2D (its picture is drawn by plot)");
  check_sizes(o);
  return render_detail::in_arena(o.threads, [&] {
    MeshOptions mo;
    mo.resolution = o.resolution;
    mo.threads = o.threads;
    const TriangleMesh mesh = extract_mesh(tree, params, mo);
    if (mesh.triangles.empty()) {
      throw InputError("render: the 0.5 level set is empty in the domain");
    }
    const std::vector<Camera> cameras = cameras_of(mesh, o);
    for (const Camera& c : cameras) check_camera(c, tree, params);
    return shade_views(mesh, cameras, o);
  });
}

std::string render_mesh_png(const TriangleMesh& mesh, const RenderOptions& o) {
  check_sizes(o);
  if (mesh.triangles.empty()) throw InputError("render: the mesh has no triangles");
  return render_detail::in_arena(o.threads, [&] {
    const std::vector<Camera> cameras = cameras_of(mesh, o);
    for (const Camera& c : cameras) render_detail::check_camera_geometry(c);
    return shade_views(mesh, cameras, o);
  });
}

}  // namespace fuzzycsg
