#pragma once
// The forward visibility as it was first written (one ray at a time, a fresh Embree device per
// frame, the tree evaluated recursively at every crossing), with one later change (the surface
// shown where coplanar faces of several primitives are crossed at once): the reference that
// the faster render_visibility must reproduce to the bit.
#include <embree3/rtcore.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numbers>
#include <thread>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/diffcsg/visibility.hpp"

namespace fuzzycsg::diffcsg::reference {

inline Vec3 normalised(const Vec3& v) {
  const double n = std::sqrt(dot(v, v));
  return n > 0 ? Vec3{v[0] / n, v[1] / n, v[2] / n} : v;
}

// Camera::ray as first written: the axes, tan and the aspect computed for every pixel.
inline Vec3 reference_ray(const Camera& camera, int i, int j) {
  Vec3 forward, right, true_up;
  forward = normalised(sub(camera.target, camera.eye));
  right = cross(forward, camera.up);
  if (dot(right, right) < 1e-24) right = cross(forward, Vec3{1, 0, 0});
  right = normalised(right);
  true_up = cross(right, forward);
  const double half = std::tan(camera.fov_deg * std::numbers::pi / 360);
  const double aspect = static_cast<double>(camera.width) / camera.height;
  const double x = (2 * (i + 0.5) / camera.width - 1) * half * aspect;
  const double y = (1 - 2 * (j + 0.5) / camera.height) * half;
  return normalised({forward[0] + x * right[0] + y * true_up[0],
                     forward[1] + x * right[1] + y * true_up[1],
                     forward[2] + x * right[2] + y * true_up[2]});
}

struct Hit {
  float t, u, v;
  unsigned geometry, triangle;
  int sign;  // +1 entering, -1 leaving, 0 grazing
};

// One primitive's crossing of the ray at one depth.
struct Crossing {
  std::size_t hit;  // its first hit
  unsigned geometry;
  int sign;
  std::size_t group;  // the first hit of its depth
};

// Every hit along the ray: the filter records the hit and rejects it, so that traversal goes
// on to the end of the ray.
struct Collector {
  RTCIntersectContext context;
  std::vector<Hit>* hits;
};

inline void collect(const RTCFilterFunctionNArguments* args) {
  args->valid[0] = 0;
  auto* c = reinterpret_cast<Collector*>(args->context);
  const RTCHit* hit = reinterpret_cast<const RTCHit*>(args->hit);
  const RTCRay* ray = reinterpret_cast<const RTCRay*>(args->ray);
  c->hits->push_back({ray->tfar, hit->u, hit->v, hit->geomID, hit->primID, 0});
}

struct DeviceDeleter {
  void operator()(RTCDevice d) const { rtcReleaseDevice(d); }
};
struct SceneDeleter {
  void operator()(RTCScene s) const { rtcReleaseScene(s); }
};

inline Frame reference_visibility(const Scene& scene, const Camera& camera, int threads) {
  std::unique_ptr<RTCDeviceTy, DeviceDeleter> device(rtcNewDevice(nullptr));
  if (!device) throw Error("Embree: cannot create a device");
  std::unique_ptr<RTCSceneTy, SceneDeleter> rtc(rtcNewScene(device.get()));
  rtcSetSceneFlags(rtc.get(), RTC_SCENE_FLAG_ROBUST | RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION);
  rtcSetSceneBuildQuality(rtc.get(), RTC_BUILD_QUALITY_HIGH);
  for (std::size_t p = 0; p < scene.primitives.size(); ++p) {
    const TriangleMesh& m = scene.primitives[p].mesh;
    RTCGeometry g = rtcNewGeometry(device.get(), RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(
        g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), m.vertices.size()));
    auto* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
        g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), m.triangles.size()));
    for (std::size_t v = 0; v < m.vertices.size(); ++v) {
      for (int k = 0; k < 3; ++k) vb[v * 3 + k] = static_cast<float>(m.vertices[v][k]);
    }
    for (std::size_t t = 0; t < m.triangles.size(); ++t) {
      for (int k = 0; k < 3; ++k) ib[t * 3 + k] = static_cast<unsigned>(m.triangles[t][k]);
    }
    rtcCommitGeometry(g);
    rtcAttachGeometryByID(rtc.get(), g, static_cast<unsigned>(p));
    rtcReleaseGeometry(g);
  }
  const int n_threads =
      threads > 0 ? threads : std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  tbb::task_arena arena(n_threads);
  arena.execute([&] { rtcCommitScene(rtc.get()); });
  if (rtcGetDeviceError(device.get()) != RTC_ERROR_NONE) throw Error("Embree: scene build failed");

  Frame f;
  f.width = camera.width;
  f.height = camera.height;
  const std::size_t pixels = static_cast<std::size_t>(f.width) * f.height;
  f.primitive.assign(pixels, -1);
  f.triangle.assign(pixels, -1);
  f.depth.assign(pixels, std::numeric_limits<float>::infinity());
  f.barycentric.assign(pixels, {0, 0});
  f.normal.assign(pixels, {0, 0, 0});
  const std::size_t np = scene.primitives.size();
  arena.execute([&] {
    tbb::parallel_for(
        tbb::blocked_range<int>(0, f.height), [&](const tbb::blocked_range<int>& rows) {
          std::vector<Hit> hits;
          std::vector<std::uint8_t> inside(np);
          std::vector<int> winding(np);
          std::vector<Crossing> crossings;
          Collector c;
          c.hits = &hits;
          for (int j = rows.begin(); j != rows.end(); ++j) {
            for (int i = 0; i < f.width; ++i) {
              const Vec3 d = reference_ray(camera, i, j);
              hits.clear();
              rtcInitIntersectContext(&c.context);
              c.context.filter = collect;
              RTCRayHit rh;
              rh.ray.org_x = static_cast<float>(camera.eye[0]);
              rh.ray.org_y = static_cast<float>(camera.eye[1]);
              rh.ray.org_z = static_cast<float>(camera.eye[2]);
              rh.ray.dir_x = static_cast<float>(d[0]);
              rh.ray.dir_y = static_cast<float>(d[1]);
              rh.ray.dir_z = static_cast<float>(d[2]);
              rh.ray.tnear = 0;
              rh.ray.tfar = std::numeric_limits<float>::infinity();
              rh.ray.time = 0;
              rh.ray.mask = ~0u;
              rh.ray.id = 0;
              rh.ray.flags = 0;
              rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
              rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
              rtcIntersect1(rtc.get(), &c.context, &rh);
              if (hits.empty()) continue;
              std::sort(hits.begin(), hits.end(), [](const Hit& a, const Hit& b) {
                return a.t != b.t ? a.t < b.t
                                  : (a.geometry != b.geometry ? a.geometry < b.geometry
                                                              : a.triangle < b.triangle);
              });
              // A BVH may report a triangle twice: keep one of each.
              hits.erase(std::unique(hits.begin(), hits.end(),
                                     [](const Hit& a, const Hit& b) {
                                       return a.t == b.t && a.geometry == b.geometry &&
                                              a.triangle == b.triangle;
                                     }),
                         hits.end());
              // Each hit enters its primitive (the face's outward normal against the ray) or
              // leaves it. A ray through an edge or a vertex meets every face there at the same
              // depth: those hits are one crossing of that primitive, entering or leaving by their
              // majority (none at a silhouette, where they tie). The ray ends outside every
              // primitive, so the camera's winding number in a primitive is minus the sum of its
              // crossings (a camera inside a primitive is handled); a point is inside where its
              // winding number is positive.
              for (Hit& h : hits) {
                const TriangleMesh& m = scene.primitives[h.geometry].mesh;
                const auto& tri = m.triangles[h.triangle];
                const Vec3 n = cross(sub(m.vertices[static_cast<std::size_t>(tri[1])],
                                         m.vertices[static_cast<std::size_t>(tri[0])]),
                                     sub(m.vertices[static_cast<std::size_t>(tri[2])],
                                         m.vertices[static_cast<std::size_t>(tri[0])]));
                const double side = dot(n, d);
                h.sign = side < 0 ? 1 : (side > 0 ? -1 : 0);
              }
              const float scale = std::max(1.0f, hits.back().t);
              crossings.clear();
              for (std::size_t k = 0; k < hits.size();) {
                std::size_t e = k;
                while (e < hits.size() && hits[e].t - hits[k].t <= 1e-6f * scale) ++e;
                // Hits [k, e) are at one depth: one crossing per primitive among them.
                for (std::size_t q = k; q < e; ++q) {
                  bool first = true;
                  int sum = 0;
                  for (std::size_t r = k; r < e; ++r) {
                    if (hits[r].geometry != hits[q].geometry) continue;
                    if (r < q) first = false;
                    sum += hits[r].sign;
                  }
                  if (first) crossings.push_back({q, hits[q].geometry, (sum > 0) - (sum < 0), k});
                }
                k = e;
              }
              std::fill(winding.begin(), winding.end(), 0);
              for (const Crossing& x : crossings) winding[x.geometry] -= x.sign;
              for (std::size_t p = 0; p < np; ++p) inside[p] = winding[p] > 0;
              bool solid = scene.solid(inside);
              for (std::size_t k = 0; k < crossings.size();) {
                // Crossings at one depth (coplanar faces of different primitives) act together.
                std::size_t e = k;
                while (e < crossings.size() && crossings[e].group == crossings[k].group) {
                  winding[crossings[e].geometry] += crossings[e].sign;
                  inside[crossings[e].geometry] = winding[crossings[e].geometry] > 0;
                  ++e;
                }
                const bool now = scene.solid(inside);
                if (!solid && now) {
                  // Of the crossings that enter or leave, the first the solid needs; else the
                  // first that enters or leaves; else the first. (The first implementation took
                  // the first that enters or leaves: the rule changed after OpenCSG showed a
                  // bar's top where a subtracted cylinder's coplanar cap had been shown.)
                  std::size_t shown = e;
                  for (std::size_t q = k; q < e && shown == e && e - k > 1; ++q) {
                    if (crossings[q].sign == 0) continue;
                    const unsigned g = crossings[q].geometry;
                    const std::uint8_t with = inside[g];
                    inside[g] = winding[g] - crossings[q].sign > 0;
                    if (!scene.solid(inside)) shown = q;
                    inside[g] = with;
                  }
                  for (std::size_t q = k; q < e && shown == e; ++q) {
                    if (crossings[q].sign != 0) shown = q;
                  }
                  if (shown == e) shown = k;
                  const Hit& h = hits[crossings[shown].hit];
                  const std::size_t px = static_cast<std::size_t>(j) * f.width + i;
                  const TriangleMesh& m = scene.primitives[h.geometry].mesh;
                  const auto& tri = m.triangles[h.triangle];
                  Vec3 n = normalised(cross(sub(m.vertices[static_cast<std::size_t>(tri[1])],
                                                m.vertices[static_cast<std::size_t>(tri[0])]),
                                            sub(m.vertices[static_cast<std::size_t>(tri[2])],
                                                m.vertices[static_cast<std::size_t>(tri[0])])));
                  if (dot(n, d) > 0) n = {-n[0], -n[1], -n[2]};
                  f.primitive[px] = static_cast<int>(h.geometry);
                  f.triangle[px] = static_cast<int>(h.triangle);
                  f.depth[px] = h.t;
                  f.barycentric[px] = {h.u, h.v};
                  f.normal[px] = {static_cast<float>(n[0]), static_cast<float>(n[1]),
                                  static_cast<float>(n[2])};
                  break;
                }
                solid = now;
                k = e;
              }
            }
          }
        });
  });
  return f;
}

}  // namespace fuzzycsg::diffcsg::reference
