#include "fuzzycsg/diffcsg/antialias.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <utility>

#include "fuzzycsg/core/error.hpp"

namespace fuzzycsg::diffcsg {

Topology opposite_vertices(const Scene& scene) {
  Topology out(scene.primitives.size());
  for (std::size_t p = 0; p < scene.primitives.size(); ++p) {
    const TriMesh& m = scene.primitives[p];
    std::map<std::pair<int, int>, std::vector<std::pair<int, int>>> edges;  // -> (tri, k)
    for (std::size_t t = 0; t < m.triangles.size(); ++t) {
      for (int k = 0; k < 3; ++k) {
        const int a = m.triangles[t][static_cast<std::size_t>((k + 1) % 3)];
        const int b = m.triangles[t][static_cast<std::size_t>((k + 2) % 3)];
        edges[{std::min(a, b), std::max(a, b)}].emplace_back(static_cast<int>(t), k);
      }
    }
    out[p].resize(m.triangles.size());
    for (std::size_t t = 0; t < m.triangles.size(); ++t) {
      for (int k = 0; k < 3; ++k) {
        const int a = m.triangles[t][static_cast<std::size_t>((k + 1) % 3)];
        const int b = m.triangles[t][static_cast<std::size_t>((k + 2) % 3)];
        int opposite = m.triangles[t][static_cast<std::size_t>(k)];
        for (const auto& [u, kk] : edges[{std::min(a, b), std::max(a, b)}]) {
          if (u != static_cast<int>(t)) {
            opposite = m.triangles[static_cast<std::size_t>(u)][static_cast<std::size_t>(kk)];
            break;
          }
        }
        out[p][t][static_cast<std::size_t>(k)] = opposite;
      }
    }
  }
  return out;
}

namespace {

struct CameraFrame {
  Vec3 eye, forward, right, up;
  double half = 1, aspect = 1;
  int width = 1, height = 1;
};

CameraFrame camera_frame(const Camera& c) {
  CameraFrame f;
  f.eye = c.eye;
  c.axes(f.forward, f.right, f.up);
  f.half = std::tan(c.fov_deg * std::numbers::pi / 360);
  f.aspect = static_cast<double>(c.width) / c.height;
  f.width = c.width;
  f.height = c.height;
  return f;
}

Projection project(const CameraFrame& f, const Vec3& p) {
  const Vec3 d = sub(p, f.eye);
  const double xc = dot(d, f.right), yc = dot(d, f.up), zc = dot(d, f.forward);
  Projection out;
  const double kx = f.width / (2 * f.half * f.aspect), ky = f.height / (2 * f.half);
  out.sx = f.width / 2.0 + kx * xc / zc;
  out.sy = f.height / 2.0 - ky * yc / zc;
  for (int k = 0; k < 3; ++k) {
    const std::size_t kk = static_cast<std::size_t>(k);
    out.jacobian[kk] = kx * (f.right[kk] * zc - xc * f.forward[kk]) / (zc * zc);
    out.jacobian[3 + kk] = -ky * (f.up[kk] * zc - yc * f.forward[kk]) / (zc * zc);
  }
  return out;
}

double cross2(double ax, double ay, double bx, double by) { return ax * by - ay * bx; }

}  // namespace

Projection project(const Camera& camera, const Vec3& p) { return project(camera_frame(camera), p); }

Image antialias(const Scene& scene, const Topology& topology, const Camera& camera,
                const Frame& frame, const Image& colour, std::vector<AaPair>* pairs) {
  if (colour.width != frame.width || colour.height != frame.height) {
    throw Error("antialias: the colour image's size differs from the frame's");
  }
  const CameraFrame cf = camera_frame(camera);
  Image out = colour;
  if (pairs) pairs->clear();
  const int w = frame.width, h = frame.height, ch = colour.channels;
  for (int j = 0; j < h; ++j) {
    for (int i = 0; i < w; ++i) {
      for (int dir = 0; dir < 2; ++dir) {
        const int i1 = i + (dir == 0 ? 1 : 0), j1 = j + (dir == 1 ? 1 : 0);
        if (i1 >= w || j1 >= h) continue;
        const std::size_t p0 = static_cast<std::size_t>(j) * w + i;
        const std::size_t p1 = static_cast<std::size_t>(j1) * w + i1;
        const int pr0 = frame.primitive[p0], pr1 = frame.primitive[p1];
        if (pr0 == pr1 && frame.triangle[p0] == frame.triangle[p1]) continue;
        // The triangle in front, or the only one.
        bool from0 = pr1 < 0 || (pr0 >= 0 && frame.depth[p0] <= frame.depth[p1]);
        const std::size_t src = from0 ? p0 : p1;
        const int s = from0 ? 1 : -1;
        const int prim = frame.primitive[src], tri = frame.triangle[src];
        const TriMesh& m = scene.primitives[static_cast<std::size_t>(prim)];
        const auto& t = m.triangles[static_cast<std::size_t>(tri)];
        const double ox = (src % static_cast<std::size_t>(w)) + 0.5;
        const double oy = static_cast<double>(src / static_cast<std::size_t>(w)) + 0.5;
        const auto local = [&](int vertex, double& x, double& y) {
          const Projection pr = project(cf, m.vertices[static_cast<std::size_t>(vertex)]);
          x = pr.sx - ox;
          y = pr.sy - oy;
          if (dir == 1) std::swap(x, y);
        };
        double vx[3], vy[3];
        for (int k = 0; k < 3; ++k) local(t[static_cast<std::size_t>(k)], vx[k], vy[k]);
        const double bb = cross2(vx[1] - vx[0], vy[1] - vy[0], vx[2] - vx[0], vy[2] - vy[0]);
        int best = -1;
        double best_t = -HUGE_VAL;
        for (int k = 0; k < 3; ++k) {
          const int a = (k + 1) % 3, b = (k + 2) % 3;
          if ((vy[a] < 0) == (vy[b] < 0)) continue;
          const double tk = s * (vx[a] * vy[b] - vx[b] * vy[a]) / (vy[b] - vy[a]);
          if (tk > best_t) {
            best_t = tk;
            best = k;
          }
        }
        if (best < 0) continue;
        // Silhouette: the neighbour across the edge faces the other way on screen.
        double qx[3] = {vx[0], vx[1], vx[2]}, qy[3] = {vy[0], vy[1], vy[2]};
        local(topology[static_cast<std::size_t>(prim)][static_cast<std::size_t>(tri)]
                      [static_cast<std::size_t>(best)],
              qx[best], qy[best]);
        const double ak = cross2(qx[1] - qx[0], qy[1] - qy[0], qx[2] - qx[0], qy[2] - qy[0]);
        if (std::signbit(ak) != std::signbit(bb)) continue;
        const int a = (best + 1) % 3, b = (best + 2) % 3;
        if (std::abs(vy[b] - vy[a]) < std::abs(vx[b] - vx[a])) continue;
        if (!(best_t > -1.0 / 16 && best_t < 17.0 / 16)) continue;
        const double th = std::clamp(best_t, 0.0, 1.0);
        const double alpha = s * (0.5 - th);
        const std::size_t target = alpha > 0 ? p0 : p1;
        for (int c = 0; c < ch; ++c) {
          out.at(target)[c] += static_cast<float>(alpha * (colour.at(p1)[c] - colour.at(p0)[c]));
        }
        if (pairs) {
          pairs->push_back({p0, p1, target, prim, tri, best, s, dir == 1, alpha});
        }
      }
    }
  }
  return out;
}

void antialias_backward(const Scene& scene, const Camera& camera, const Image& colour,
                        const std::vector<AaPair>& pairs, const Image& grad_out, Image& grad_colour,
                        std::vector<std::vector<Vec3>>& grad_vertices) {
  const CameraFrame cf = camera_frame(camera);
  const int ch = colour.channels;
  if (grad_colour.data.size() != colour.data.size()) {
    grad_colour = colour;
    std::fill(grad_colour.data.begin(), grad_colour.data.end(), 0.0f);
  }
  for (std::size_t k = 0; k < grad_out.data.size(); ++k) grad_colour.data[k] += grad_out.data[k];
  grad_vertices.resize(scene.primitives.size());
  for (std::size_t p = 0; p < scene.primitives.size(); ++p) {
    grad_vertices[p].resize(scene.primitives[p].vertices.size(), Vec3{0, 0, 0});
  }
  const int w = colour.width;
  for (const AaPair& pr : pairs) {
    const float* g = grad_out.at(pr.target);
    double delta = 0;
    for (int c = 0; c < ch; ++c) {
      grad_colour.at(pr.p0)[c] -= static_cast<float>(pr.alpha * g[c]);
      grad_colour.at(pr.p1)[c] += static_cast<float>(pr.alpha * g[c]);
      delta += g[c] * (colour.at(pr.p1)[c] - colour.at(pr.p0)[c]);
    }
    if (!(std::abs(pr.alpha) < 0.5)) continue;
    const TriMesh& m = scene.primitives[static_cast<std::size_t>(pr.primitive)];
    const auto& t = m.triangles[static_cast<std::size_t>(pr.triangle)];
    const std::size_t src = pr.s > 0 ? pr.p0 : pr.p1;
    const double ox = (src % static_cast<std::size_t>(w)) + 0.5;
    const double oy = static_cast<double>(src / static_cast<std::size_t>(w)) + 0.5;
    const int i1 = t[static_cast<std::size_t>((pr.edge + 1) % 3)];
    const int i2 = t[static_cast<std::size_t>((pr.edge + 2) % 3)];
    const Projection a = project(cf, m.vertices[static_cast<std::size_t>(i1)]);
    const Projection b = project(cf, m.vertices[static_cast<std::size_t>(i2)]);
    double x1 = a.sx - ox, y1 = a.sy - oy, x2 = b.sx - ox, y2 = b.sy - oy;
    if (pr.vertical) {
      std::swap(x1, y1);
      std::swap(x2, y2);
    }
    const double dx = x2 - x1, dy = y2 - y1;
    const double d = dy + 1e-3 * (dy > 0 ? 1 : (dy < 0 ? -1 : 0));
    if (d == 0) continue;
    const double xc = (x1 * dy - y1 * dx) / d;
    double da_dx1 = -y2 / d, da_dx2 = y1 / d, da_dy1 = -(xc - x2) / d, da_dy2 = (xc - x1) / d;
    if (pr.vertical) {  // back to screen axes
      std::swap(da_dx1, da_dy1);
      std::swap(da_dx2, da_dy2);
    }
    const auto add = [&](int vertex, const Projection& pj, double gx, double gy) {
      Vec3& out =
          grad_vertices[static_cast<std::size_t>(pr.primitive)][static_cast<std::size_t>(vertex)];
      for (int k = 0; k < 3; ++k) {
        out[static_cast<std::size_t>(k)] +=
            delta * (gx * pj.jacobian[static_cast<std::size_t>(k)] +
                     gy * pj.jacobian[3 + static_cast<std::size_t>(k)]);
      }
    };
    add(i1, a, da_dx1, da_dy1);
    add(i2, b, da_dx2, da_dy2);
  }
}

}  // namespace fuzzycsg::diffcsg
