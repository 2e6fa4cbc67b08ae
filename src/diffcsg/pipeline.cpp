#include "fuzzycsg/diffcsg/pipeline.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <utility>

namespace fuzzycsg::diffcsg {

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

}  // namespace

PreparedScene prepare_scene(Scene scene, bool intersection_aa) {
  PreparedScene out;
  out.scene = std::move(scene);
  out.topology = opposite_vertices(out.scene);
  out.normals = corner_normals(out.scene);
  out.intersection_aa = intersection_aa;
  if (intersection_aa) {
    const auto t0 = Clock::now();
    out.edges = intersection_edges(out.scene);
    out.seconds_edges = since(t0);
  }
  return out;
}

ViewPass render_view(const PreparedScene& s, const Camera& camera, Shading shading, int threads) {
  ViewPass pass;
  render_view(s, camera, shading, threads, pass);
  return pass;
}

void render_view(const PreparedScene& s, const Camera& camera, Shading shading, int threads,
                 ViewPass& pass) {
  auto t0 = Clock::now();
  render_visibility(s.scene, camera, pass.frame, threads);
  pass.seconds_visibility = since(t0);
  t0 = Clock::now();
  shade(s.scene, s.normals, camera, pass.frame, shading, pass.shaded, &pass.record);
  antialias(s.scene, s.topology, camera, pass.frame, pass.shaded, pass.image, &pass.pairs,
            s.intersection_aa ? &s.edges : nullptr);
  pass.seconds_antialias = since(t0);
}

void render_view_backward(const PreparedScene& s, const Camera& camera, Shading shading,
                          const ViewPass& pass, const Image& grad, VertexGradient& grad_vertices) {
  Image& grad_shaded = pass.grad_shaded;
  grad_shaded.width = pass.shaded.width;
  grad_shaded.height = pass.shaded.height;
  grad_shaded.channels = pass.shaded.channels;
  grad_shaded.data.assign(pass.shaded.data.size(), 0.0f);
  antialias_backward(s.scene, camera, pass.shaded, pass.pairs, grad, grad_shaded, grad_vertices,
                     s.intersection_aa ? &s.edges : nullptr);
  shade_backward(s.scene, s.normals, camera, pass.frame, shading, pass.record, grad_shaded,
                 grad_vertices);
}

Image render_image(const PreparedScene& scene, const Camera& camera, Shading shading, int threads) {
  return render_view(scene, camera, shading, threads).image;
}

std::vector<Camera> orbit_views(const Vec3& centre, double distance, int n, double elevation,
                                int width, int height, double fov_deg) {
  std::vector<Camera> out;
  for (int v = 0; v < n; ++v) {
    out.push_back(
        Camera::orbit(centre, 30 + 360.0 * v / n, elevation, distance, width, height, fov_deg));
  }
  return out;
}

Camera random_view(const Vec3& centre, double distance, double u1, double u2, int width, int height,
                   double fov_deg) {
  const double theta = std::numbers::pi * u1, phi = 2 * std::numbers::pi * u2;
  Camera c;
  c.target = centre;
  c.eye = {centre[0] + distance * std::sin(theta) * std::cos(phi),
           centre[1] + distance * std::sin(theta) * std::sin(phi),
           centre[2] + distance * std::cos(theta)};
  c.up = {0, 0, 1};
  c.width = width;
  c.height = height;
  c.fov_deg = fov_deg;
  return c;
}

double framing_distance(const Scene& scene, const Vec3& centre, double fov_deg, double margin) {
  const auto [lo, hi] = scene.bounds();
  double r2 = 0;
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3 p{(corner & 1) ? hi[0] : lo[0], (corner & 2) ? hi[1] : lo[1],
                 (corner & 4) ? hi[2] : lo[2]};
    const Vec3 d = sub(p, centre);
    r2 = std::max(r2, dot(d, d));
  }
  const double r = std::max(std::sqrt(r2), 1e-9);
  return r / std::sin(fov_deg * std::numbers::pi / 360) * margin;
}

}  // namespace fuzzycsg::diffcsg
