#include "fuzzycsg/diffcsg/shade.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <utility>

#include "fuzzycsg/core/error.hpp"

namespace fuzzycsg::diffcsg {

std::string_view shading_name(Shading s) { return s == Shading::kNormals ? "normals" : "colours"; }

std::optional<Shading> shading_from_name(std::string_view name) {
  if (name == "normals") return Shading::kNormals;
  if (name == "colours" || name == "colors") return Shading::kColours;
  return std::nullopt;
}

std::array<float, 3> primitive_colour(int p) {
  static constexpr std::array<std::array<float, 3>, 10> kPalette{{{31, 119, 180},
                                                                  {255, 127, 14},
                                                                  {44, 160, 44},
                                                                  {214, 39, 40},
                                                                  {148, 103, 189},
                                                                  {140, 86, 75},
                                                                  {227, 119, 194},
                                                                  {127, 127, 127},
                                                                  {188, 189, 34},
                                                                  {23, 190, 207}}};
  const auto& c = kPalette[static_cast<std::size_t>(p) % kPalette.size()];
  return {c[0] / 255.0f, c[1] / 255.0f, c[2] / 255.0f};
}

namespace {

Vec3 face_cross(const TriangleMesh& m, std::size_t t) {
  const auto& tri = m.triangles[t];
  const Vec3& a = m.vertices[static_cast<std::size_t>(tri[0])];
  return cross(sub(m.vertices[static_cast<std::size_t>(tri[1])], a),
               sub(m.vertices[static_cast<std::size_t>(tri[2])], a));
}

// The camera in clip terms: X = (v - eye) . right / (h a), Y = (v - eye) . up / h,
// W = (v - eye) . forward, so that (X / W, Y / W) is in [-1, 1]^2 over the image.
struct Clip {
  Vec3 eye, forward, right, up;
  double kx = 1, ky = 1;
  int width = 1, height = 1;
  explicit Clip(const Camera& c) : eye(c.eye), width(c.width), height(c.height) {
    c.axes(forward, right, up);
    const double h = std::tan(c.fov_deg * std::numbers::pi / 360);
    ky = 1 / h;
    kx = 1 / (h * static_cast<double>(c.width) / c.height);
  }
  std::array<double, 3> of(const Vec3& v) const {
    const Vec3 d = sub(v, eye);
    return {dot(d, right) * kx, dot(d, up) * ky, dot(d, forward)};
  }
  double fx(int i) const { return 2 * (i + 0.5) / width - 1; }
  double fy(int j) const { return 1 - 2 * (j + 0.5) / height; }
  // The direction of pixel (i, j)'s ray (not of unit length).
  Vec3 ray(int i, int j) const {
    const double x = fx(i) / kx, y = fy(j) / ky;
    return {forward[0] + x * right[0] + y * up[0], forward[1] + x * right[1] + y * up[1],
            forward[2] + x * right[2] + y * up[2]};
  }
};

std::array<double, 3> barycentrics(const Clip& clip, int i, int j, const Vec3& a, const Vec3& b,
                                   const Vec3& c, std::array<std::array<double, 2>, 3>* p_out,
                                   double* sum_out) {
  const double fx = clip.fx(i), fy = clip.fy(j);
  std::array<std::array<double, 2>, 3> p;
  const Vec3* v[3] = {&a, &b, &c};
  for (std::size_t k = 0; k < 3; ++k) {
    const auto x = clip.of(*v[k]);
    p[k] = {x[0] - fx * x[2], x[1] - fy * x[2]};
  }
  const auto cr = [](const std::array<double, 2>& u, const std::array<double, 2>& w) {
    return u[0] * w[1] - u[1] * w[0];
  };
  const double a0 = cr(p[1], p[2]), a1 = cr(p[2], p[0]), a2 = cr(p[0], p[1]);
  const double s = a0 + a1 + a2;
  if (p_out) *p_out = p;
  if (sum_out) *sum_out = s;
  if (s == 0) return {1.0 / 3, 1.0 / 3, 1.0 / 3};
  return {a0 / s, a1 / s, a2 / s};
}

void barycentrics_vjp(const Clip& clip, int i, int j, const Vec3& a, const Vec3& b, const Vec3& c,
                      const std::array<double, 3>& g, Vec3& ga, Vec3& gb, Vec3& gc) {
  std::array<std::array<double, 2>, 3> p;
  double s = 0;
  const std::array<double, 3> bary = barycentrics(clip, i, j, a, b, c, &p, &s);
  if (s == 0) return;
  const double mean = g[0] * bary[0] + g[1] * bary[1] + g[2] * bary[2];
  const double g0 = (g[0] - mean) / s, g1 = (g[1] - mean) / s, g2 = (g[2] - mean) / s;
  std::array<std::array<double, 2>, 3> gp{};
  // a0 = p1 x p2, a1 = p2 x p0, a2 = p0 x p1 (2D cross products).
  gp[1][0] += g0 * p[2][1];
  gp[1][1] -= g0 * p[2][0];
  gp[2][0] -= g0 * p[1][1];
  gp[2][1] += g0 * p[1][0];
  gp[2][0] += g1 * p[0][1];
  gp[2][1] -= g1 * p[0][0];
  gp[0][0] -= g1 * p[2][1];
  gp[0][1] += g1 * p[2][0];
  gp[0][0] += g2 * p[1][1];
  gp[0][1] -= g2 * p[1][0];
  gp[1][0] -= g2 * p[0][1];
  gp[1][1] += g2 * p[0][0];
  const double fx = clip.fx(i), fy = clip.fy(j);
  Vec3* out[3] = {&ga, &gb, &gc};
  for (std::size_t k = 0; k < 3; ++k) {
    const double gx = gp[k][0], gy = gp[k][1], gw = -fx * gp[k][0] - fy * gp[k][1];
    for (std::size_t d = 0; d < 3; ++d) {
      (*out[k])[d] +=
          gx * clip.kx * clip.right[d] + gy * clip.ky * clip.up[d] + gw * clip.forward[d];
    }
  }
}

}  // namespace

std::array<double, 3> pixel_barycentrics(const Camera& camera, int i, int j, const Vec3& a,
                                         const Vec3& b, const Vec3& c) {
  return barycentrics(Clip(camera), i, j, a, b, c, nullptr, nullptr);
}

void pixel_barycentrics_vjp(const Camera& camera, int i, int j, const Vec3& a, const Vec3& b,
                            const Vec3& c, const std::array<double, 3>& g, Vec3& ga, Vec3& gb,
                            Vec3& gc) {
  barycentrics_vjp(Clip(camera), i, j, a, b, c, g, ga, gb, gc);
}

CornerNormals corner_normals(const Scene& scene) {
  CornerNormals out;
  out.primitives.resize(scene.primitives.size());
  for (std::size_t p = 0; p < scene.primitives.size(); ++p) {
    const TriangleMesh& m = scene.primitives[p].mesh;
    const std::vector<int>& smoothing = scene.primitives[p].smoothing;
    CornerNormals::Primitive& cp = out.primitives[p];
    cp.corner_slot.resize(m.triangles.size());
    std::map<std::pair<int, int>, int> slots;  // (vertex, group) -> slot
    for (std::size_t t = 0; t < m.triangles.size(); ++t) {
      const int group = smoothing.empty() ? -1 : smoothing[t];
      if (group < 0) {
        const int slot = static_cast<int>(cp.slot_triangles.size());
        cp.slot_triangles.push_back({static_cast<int>(t)});
        cp.corner_slot[t] = {slot, slot, slot};
        continue;
      }
      for (std::size_t k = 0; k < 3; ++k) {
        const auto [it, added] = slots.try_emplace({m.triangles[t][k], group},
                                                   static_cast<int>(cp.slot_triangles.size()));
        if (added) cp.slot_triangles.emplace_back();
        cp.slot_triangles[static_cast<std::size_t>(it->second)].push_back(static_cast<int>(t));
        cp.corner_slot[t][k] = it->second;
      }
    }
    cp.slot_sum.assign(cp.slot_triangles.size(), Vec3{0, 0, 0});
    cp.slot_normal.assign(cp.slot_triangles.size(), Vec3{0, 0, 0});
    for (std::size_t s = 0; s < cp.slot_triangles.size(); ++s) {
      Vec3& sum = cp.slot_sum[s];
      for (const int t : cp.slot_triangles[s]) {
        const Vec3 n = face_cross(m, static_cast<std::size_t>(t));
        for (std::size_t k = 0; k < 3; ++k) sum[k] += n[k];
      }
      const double len = std::sqrt(dot(sum, sum));
      if (len > 0) cp.slot_normal[s] = {sum[0] / len, sum[1] / len, sum[2] / len};
    }
  }
  return out;
}

Image shade(const Scene& scene, const CornerNormals& normals, const Camera& camera,
            const Frame& frame, Shading shading, ShadeRecord* record) {
  Image img;
  shade(scene, normals, camera, frame, shading, img, record);
  return img;
}

void shade(const Scene& scene, const CornerNormals& normals, const Camera& camera,
           const Frame& frame, Shading shading, Image& img, ShadeRecord* record) {
  if (frame.width != camera.width || frame.height != camera.height) {
    throw Error("shade: the frame's size differs from the camera's");
  }
  const std::size_t pixels = frame.primitive.size();
  img.width = frame.width;
  img.height = frame.height;
  img.channels = 3;
  img.data.assign(pixels * 3, 0.0f);
  if (record) record->flip.assign(pixels, 1);
  const Clip clip(camera);
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, pixels, 4096),
      [&](const tbb::blocked_range<std::size_t>& range) {
        for (std::size_t px = range.begin(); px != range.end(); ++px) {
          const int prim = frame.primitive[px];
          if (prim < 0) continue;
          float* o = img.at(px);
          if (shading == Shading::kColours) {
            const auto c = primitive_colour(prim);
            for (std::size_t k = 0; k < 3; ++k) o[k] = c[k];
            continue;
          }
          const TriangleMesh& m = scene.primitives[static_cast<std::size_t>(prim)].mesh;
          const std::size_t t = static_cast<std::size_t>(frame.triangle[px]);
          const auto& tri = m.triangles[t];
          const int i = static_cast<int>(px % static_cast<std::size_t>(frame.width));
          const int j = static_cast<int>(px / static_cast<std::size_t>(frame.width));
          const std::array<double, 3> b =
              barycentrics(clip, i, j, m.vertices[static_cast<std::size_t>(tri[0])],
                           m.vertices[static_cast<std::size_t>(tri[1])],
                           m.vertices[static_cast<std::size_t>(tri[2])], nullptr, nullptr);
          // A back face (its normal along the ray) is the inside of a subtracted primitive.
          const double flip = dot(face_cross(m, t), clip.ray(i, j)) > 0 ? -1.0 : 1.0;
          for (std::size_t k = 0; k < 3; ++k) {
            double v = 0;
            for (int c = 0; c < 3; ++c) {
              v += b[static_cast<std::size_t>(c)] * normals.at(prim, static_cast<int>(t), c)[k];
            }
            o[k] = static_cast<float>(flip * v);
          }
          if (record) record->flip[px] = static_cast<std::int8_t>(flip);
        }
      });
}

void shade_backward(const Scene& scene, const CornerNormals& normals, const Camera& camera,
                    const Frame& frame, Shading shading, const ShadeRecord& record,
                    const Image& grad, VertexGradient& grad_vertices) {
  grad_vertices.resize(scene);
  if (shading == Shading::kColours) return;
  // dL/d(slot normal) per primitive, with the pixel each part came from when the gradient is
  // attributed to pixels.
  const bool attribute = grad_vertices.tangent && grad_vertices.per_pixel;
  std::vector<std::vector<Vec3>> g_slot(scene.primitives.size());
  for (std::size_t p = 0; p < scene.primitives.size(); ++p) {
    g_slot[p].assign(normals.primitives[p].slot_normal.size(), Vec3{0, 0, 0});
  }
  const Clip clip(camera);
  const auto slot_backward = [&](VertexGradient& into, std::size_t p, std::size_t s, const Vec3& gn,
                                 std::size_t px) {
    // n = N / |N|, N = sum over the slot's faces of (b - a) x (c - a).
    const CornerNormals::Primitive& cp = normals.primitives[p];
    const Vec3& sum = cp.slot_sum[s];
    const double len = std::sqrt(dot(sum, sum));
    if (!(len > 0)) return;
    const Vec3& n = cp.slot_normal[s];
    const double ng = dot(n, gn);
    const Vec3 gsum{(gn[0] - n[0] * ng) / len, (gn[1] - n[1] * ng) / len,
                    (gn[2] - n[2] * ng) / len};
    const TriangleMesh& m = scene.primitives[p].mesh;
    for (const int t : cp.slot_triangles[s]) {
      const auto& tri = m.triangles[static_cast<std::size_t>(t)];
      const Vec3& a = m.vertices[static_cast<std::size_t>(tri[0])];
      const Vec3 e1 = sub(m.vertices[static_cast<std::size_t>(tri[1])], a);
      const Vec3 e2 = sub(m.vertices[static_cast<std::size_t>(tri[2])], a);
      const Vec3 g1 = cross(e2, gsum), g2 = cross(gsum, e1);
      into.add(static_cast<int>(p), tri[1], g1, px);
      into.add(static_cast<int>(p), tri[2], g2, px);
      into.add(static_cast<int>(p), tri[0], {-g1[0] - g2[0], -g1[1] - g2[1], -g1[2] - g2[2]}, px);
    }
  };
  // Blocks of pixels in parallel, each into its own accumulators, summed in block order (the
  // same result for any number of threads).
  const std::size_t pixels = frame.primitive.size();
  constexpr std::size_t kBlock = 16384;
  const std::size_t blocks = (pixels + kBlock - 1) / kBlock;
  std::vector<VertexGradient> parts(blocks);
  std::vector<std::vector<std::vector<Vec3>>> slot_parts(blocks);
  tbb::parallel_for(std::size_t{0}, blocks, [&](std::size_t block) {
    VertexGradient& part = parts[block];
    part.tangent = grad_vertices.tangent;
    part.per_pixel = grad_vertices.per_pixel;  // each block writes its own pixels only
    part.resize(scene);
    auto& gs = slot_parts[block];
    gs = g_slot;
    for (std::size_t px = block * kBlock; px < std::min(pixels, (block + 1) * kBlock); ++px) {
      const int prim = frame.primitive[px];
      if (prim < 0) continue;
      const float* g = grad.at(px);
      if (g[0] == 0 && g[1] == 0 && g[2] == 0) continue;
      const std::size_t p = static_cast<std::size_t>(prim);
      const TriangleMesh& m = scene.primitives[p].mesh;
      const std::size_t t = static_cast<std::size_t>(frame.triangle[px]);
      const auto& tri = m.triangles[t];
      const double flip = record.flip[px];
      const Vec3& va = m.vertices[static_cast<std::size_t>(tri[0])];
      const Vec3& vb = m.vertices[static_cast<std::size_t>(tri[1])];
      const Vec3& vc = m.vertices[static_cast<std::size_t>(tri[2])];
      const int i = static_cast<int>(px % static_cast<std::size_t>(frame.width));
      const int j = static_cast<int>(px / static_cast<std::size_t>(frame.width));
      const std::array<double, 3> b = barycentrics(clip, i, j, va, vb, vc, nullptr, nullptr);
      std::array<double, 3> gb{};
      for (std::size_t c = 0; c < 3; ++c) {
        const Vec3& n = normals.at(prim, static_cast<int>(t), static_cast<int>(c));
        gb[c] = flip * (g[0] * n[0] + g[1] * n[1] + g[2] * n[2]);
        const Vec3 gn{flip * b[c] * g[0], flip * b[c] * g[1], flip * b[c] * g[2]};
        const std::size_t slot = static_cast<std::size_t>(normals.primitives[p].corner_slot[t][c]);
        if (attribute) {
          slot_backward(part, p, slot, gn, px);
        } else {
          for (std::size_t k = 0; k < 3; ++k) gs[p][slot][k] += gn[k];
        }
      }
      Vec3 ga{}, gbv{}, gc{};
      barycentrics_vjp(clip, i, j, va, vb, vc, gb, ga, gbv, gc);
      part.add(prim, tri[0], ga, px);
      part.add(prim, tri[1], gbv, px);
      part.add(prim, tri[2], gc, px);
    }
  });
  for (std::size_t block = 0; block < blocks; ++block) {
    for (std::size_t p = 0; p < scene.primitives.size(); ++p) {
      for (std::size_t v = 0; v < parts[block].g[p].size(); ++v) {
        for (std::size_t k = 0; k < 3; ++k) grad_vertices.g[p][v][k] += parts[block].g[p][v][k];
      }
      if (attribute) continue;
      for (std::size_t sl = 0; sl < g_slot[p].size(); ++sl) {
        for (std::size_t k = 0; k < 3; ++k) g_slot[p][sl][k] += slot_parts[block][p][sl][k];
      }
    }
  }
  if (attribute) return;
  VertexGradient& out = grad_vertices;
  for (std::size_t p = 0; p < g_slot.size(); ++p) {
    for (std::size_t sl = 0; sl < g_slot[p].size(); ++sl) {
      const Vec3& gn = g_slot[p][sl];
      if (gn[0] != 0 || gn[1] != 0 || gn[2] != 0) slot_backward(out, p, sl, gn, 0);
    }
  }
}

}  // namespace fuzzycsg::diffcsg
