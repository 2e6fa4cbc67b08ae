#include "fuzzycsg/diffcsg/antialias.hpp"

#include <tbb/parallel_for.h>

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
    const TriangleMesh& m = scene.primitives[p].mesh;
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
                const Frame& frame, const Image& colour, std::vector<AaPair>* pairs,
                const std::vector<IntersectionEdge>* edges) {
  Image out;
  antialias(scene, topology, camera, frame, colour, out, pairs, edges);
  return out;
}

void antialias(const Scene& scene, const Topology& topology, const Camera& camera,
               const Frame& frame, const Image& colour, Image& out, std::vector<AaPair>* pairs,
               const std::vector<IntersectionEdge>* edges) {
  // Intersection edges by the pair of triangles they join.
  std::map<std::array<int, 4>, std::vector<int>> by_triangles;
  if (edges) {
    for (std::size_t e = 0; e < edges->size(); ++e) {
      const IntersectionEdge& x = (*edges)[e];
      by_triangles[{x.primitive_a, x.triangle_a, x.primitive_b, x.triangle_b}].push_back(
          static_cast<int>(e));
    }
  }
  if (colour.width != frame.width || colour.height != frame.height) {
    throw Error("antialias: the colour image's size differs from the frame's");
  }
  const CameraFrame cf = camera_frame(camera);
  // Every vertex's screen position, once.
  std::vector<std::vector<std::array<double, 2>>> screen(scene.primitives.size());
  for (std::size_t p = 0; p < scene.primitives.size(); ++p) {
    for (const Vec3& v : scene.primitives[p].mesh.vertices) {
      const Projection pr = project(cf, v);
      screen[p].push_back({pr.sx, pr.sy});
    }
  }
  const int w = frame.width, h = frame.height, ch = colour.channels;
  // The pairs of each block of rows, found in parallel; blended in row order after, so that the
  // result does not depend on the threads.
  constexpr int kRows = 8;
  const int blocks = (h + kRows - 1) / kRows;
  std::vector<std::vector<AaPair>> found_pairs(static_cast<std::size_t>(blocks));
  tbb::parallel_for(0, blocks, [&](int block) {
    std::vector<AaPair>& local_pairs = found_pairs[static_cast<std::size_t>(block)];
    for (int j = block * kRows; j < std::min(h, (block + 1) * kRows); ++j) {
      for (int i = 0; i < w; ++i) {
        for (int dir = 0; dir < 2; ++dir) {
          const int i1 = i + (dir == 0 ? 1 : 0), j1 = j + (dir == 1 ? 1 : 0);
          if (i1 >= w || j1 >= h) continue;
          const std::size_t p0 = static_cast<std::size_t>(j) * w + i;
          const std::size_t p1 = static_cast<std::size_t>(j1) * w + i1;
          const int pr0 = frame.primitive[p0], pr1 = frame.primitive[p1];
          if (pr0 == pr1 && frame.triangle[p0] == frame.triangle[p1]) continue;
          // The triangle in front, or the only one.
          const bool from0 = pr1 < 0 || (pr0 >= 0 && frame.depth[p0] <= frame.depth[p1]);
          const std::size_t src = from0 ? p0 : p1;
          const int s = from0 ? 1 : -1;
          const int prim = frame.primitive[src], tri = frame.triangle[src];
          const TriangleMesh& m = scene.primitives[static_cast<std::size_t>(prim)].mesh;
          const auto& t = m.triangles[static_cast<std::size_t>(tri)];
          const double ox = (src % static_cast<std::size_t>(w)) + 0.5;
          const double oy = static_cast<double>(src / static_cast<std::size_t>(w)) + 0.5;
          const auto& scr = screen[static_cast<std::size_t>(prim)];
          const auto local = [&](int vertex, double& x, double& y) {
            x = scr[static_cast<std::size_t>(vertex)][0] - ox;
            y = scr[static_cast<std::size_t>(vertex)][1] - oy;
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
          const auto blend = [&](double t_cross, int edge, int intersection) {
            const double th = std::clamp(t_cross, 0.0, 1.0);
            const double alpha = s * (0.5 - th);
            const std::size_t target = alpha > 0 ? p0 : p1;
            local_pairs.push_back(
                {p0, p1, target, prim, tri, edge, s, dir == 1, alpha, intersection});
          };
          bool done = false;
          if (best >= 0) {
            // Silhouette: the neighbour across the edge faces the other way on screen.
            double qx[3] = {vx[0], vx[1], vx[2]}, qy[3] = {vy[0], vy[1], vy[2]};
            local(topology[static_cast<std::size_t>(prim)][static_cast<std::size_t>(tri)]
                          [static_cast<std::size_t>(best)],
                  qx[best], qy[best]);
            const double ak = cross2(qx[1] - qx[0], qy[1] - qy[0], qx[2] - qx[0], qy[2] - qy[0]);
            const int a = (best + 1) % 3, b = (best + 2) % 3;
            if (std::signbit(ak) == std::signbit(bb) &&
                std::abs(vy[b] - vy[a]) >= std::abs(vx[b] - vx[a]) && best_t > -1.0 / 16 &&
                best_t < 17.0 / 16) {
              blend(best_t, best, -1);
              done = true;
            }
          }
          if (done || !edges || pr0 < 0 || pr1 < 0 || pr0 == pr1) continue;
          // The intersection edge of the two triangles shown, if it passes between the pixels.
          const int t0 = frame.triangle[p0], t1 = frame.triangle[p1];
          const auto hit = by_triangles.find(pr0 < pr1 ? std::array<int, 4>{pr0, t0, pr1, t1}
                                                       : std::array<int, 4>{pr1, t1, pr0, t0});
          if (hit == by_triangles.end()) continue;
          for (const int e : hit->second) {
            const IntersectionEdge& x = (*edges)[static_cast<std::size_t>(e)];
            const Projection pp = project(cf, x.p), pq = project(cf, x.q);
            double ax = pp.sx - ox, ay = pp.sy - oy, bx = pq.sx - ox, by = pq.sy - oy;
            if (dir == 1) {
              std::swap(ax, ay);
              std::swap(bx, by);
            }
            if ((ay < 0) == (by < 0)) continue;
            if (std::abs(by - ay) < std::abs(bx - ax)) continue;
            const double tc = s * (ax * by - bx * ay) / (by - ay);
            if (!(tc > -1.0 / 16 && tc < 17.0 / 16)) continue;
            blend(tc, -1, e);
            break;
          }
        }
      }
    }
  });
  out.width = colour.width;
  out.height = colour.height;
  out.channels = colour.channels;
  out.data.assign(colour.data.begin(), colour.data.end());
  if (pairs) pairs->clear();
  for (const std::vector<AaPair>& block : found_pairs) {
    for (const AaPair& pr : block) {
      for (int c = 0; c < ch; ++c) {
        out.at(pr.target)[c] +=
            static_cast<float>(pr.alpha * (colour.at(pr.p1)[c] - colour.at(pr.p0)[c]));
      }
      if (pairs) pairs->push_back(pr);
    }
  }
}

void antialias_backward(const Scene& scene, const Camera& camera, const Image& colour,
                        const std::vector<AaPair>& pairs, const Image& grad_out, Image& grad_colour,
                        std::vector<std::vector<Vec3>>& grad_vertices,
                        const std::vector<IntersectionEdge>* edges) {
  VertexGradient g;
  g.g = std::move(grad_vertices);
  antialias_backward(scene, camera, colour, pairs, grad_out, grad_colour, g, edges);
  grad_vertices = std::move(g.g);
}

void antialias_backward(const Scene& scene, const Camera& camera, const Image& colour,
                        const std::vector<AaPair>& pairs, const Image& grad_out, Image& grad_colour,
                        VertexGradient& grad_vertices, const std::vector<IntersectionEdge>* edges) {
  const CameraFrame cf = camera_frame(camera);
  const int ch = colour.channels;
  if (grad_colour.data.size() != colour.data.size()) {
    grad_colour = colour;
    std::fill(grad_colour.data.begin(), grad_colour.data.end(), 0.0f);
  }
  for (std::size_t k = 0; k < grad_out.data.size(); ++k) grad_colour.data[k] += grad_out.data[k];
  grad_vertices.resize(scene);
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
    const TriangleMesh& m = scene.primitives[static_cast<std::size_t>(pr.primitive)].mesh;
    const auto& t = m.triangles[static_cast<std::size_t>(pr.triangle)];
    const std::size_t src = pr.s > 0 ? pr.p0 : pr.p1;
    const double ox = (src % static_cast<std::size_t>(w)) + 0.5;
    const double oy = static_cast<double>(src / static_cast<std::size_t>(w)) + 0.5;
    const IntersectionEdge* x = pr.intersection >= 0 && edges
                                    ? &(*edges)[static_cast<std::size_t>(pr.intersection)]
                                    : nullptr;
    if (pr.intersection >= 0 && !x) continue;
    const int i1 = x ? -1 : t[static_cast<std::size_t>((pr.edge + 1) % 3)];
    const int i2 = x ? -1 : t[static_cast<std::size_t>((pr.edge + 2) % 3)];
    const Projection a = project(cf, x ? x->p : m.vertices[static_cast<std::size_t>(i1)]);
    const Projection b = project(cf, x ? x->q : m.vertices[static_cast<std::size_t>(i2)]);
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
      Vec3 out{};
      for (std::size_t k = 0; k < 3; ++k) {
        out[k] = delta * (gx * pj.jacobian[k] + gy * pj.jacobian[3 + k]);
      }
      grad_vertices.add(pr.primitive, vertex, out, pr.target);
    };
    if (!x) {
      add(i1, a, da_dx1, da_dy1);
      add(i2, b, da_dx2, da_dy2);
      continue;
    }
    // An intersection edge: dL/d of its endpoints, then through the edge-plane crossings to the
    // vertices of its two triangles.
    const auto endpoint = [&](const Projection& pj, double gx, double gy,
                              const EndpointSource& source) {
      Vec3 gp{};
      for (int k = 0; k < 3; ++k) {
        gp[static_cast<std::size_t>(k)] =
            delta * (gx * pj.jacobian[static_cast<std::size_t>(k)] +
                     gy * pj.jacobian[3 + static_cast<std::size_t>(k)]);
      }
      const int pe = source.of_b ? x->primitive_b : x->primitive_a;  // the crossing edge's
      const int te = source.of_b ? x->triangle_b : x->triangle_a;
      const int pt = source.of_b ? x->primitive_a : x->primitive_b;  // the crossed triangle's
      const int tt = source.of_b ? x->triangle_a : x->triangle_b;
      const TriangleMesh& me = scene.primitives[static_cast<std::size_t>(pe)].mesh;
      const TriangleMesh& mt = scene.primitives[static_cast<std::size_t>(pt)].mesh;
      const auto& tri_e = me.triangles[static_cast<std::size_t>(te)];
      const auto& tri_t = mt.triangles[static_cast<std::size_t>(tt)];
      const int v0 = tri_e[static_cast<std::size_t>(source.edge)];
      const int v1 = tri_e[static_cast<std::size_t>((source.edge + 1) % 3)];
      Vec3 g0{}, g1{}, ga{}, gb{}, gc{};
      edge_plane_point_vjp(me.vertices[static_cast<std::size_t>(v0)],
                           me.vertices[static_cast<std::size_t>(v1)],
                           mt.vertices[static_cast<std::size_t>(tri_t[0])],
                           mt.vertices[static_cast<std::size_t>(tri_t[1])],
                           mt.vertices[static_cast<std::size_t>(tri_t[2])], gp, g0, g1, ga, gb, gc);
      grad_vertices.add(pe, v0, g0, pr.target);
      grad_vertices.add(pe, v1, g1, pr.target);
      grad_vertices.add(pt, tri_t[0], ga, pr.target);
      grad_vertices.add(pt, tri_t[1], gb, pr.target);
      grad_vertices.add(pt, tri_t[2], gc, pr.target);
    };
    endpoint(a, da_dx1, da_dy1, x->p_source);
    endpoint(b, da_dx2, da_dy2, x->q_source);
  }
}

}  // namespace fuzzycsg::diffcsg
