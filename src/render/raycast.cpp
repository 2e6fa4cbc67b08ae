// A triangle mesh ray cast with Embree and shaded (raycast.hpp).
#include "raycast.hpp"

#include <embree3/rtcore.h>
#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <limits>
#include <optional>
#include <vector>

#include "fuzzycsg/core/error.hpp"

namespace fuzzycsg::render_detail {

struct DeviceDeleter {
  void operator()(RTCDevice d) const { rtcReleaseDevice(d); }
};
struct SceneDeleter {
  void operator()(RTCScene s) const { rtcReleaseScene(s); }
};

void check_camera_geometry(const Camera& c) {
  const Vec forward = sub(c.target, c.eye);
  if (!(norm(forward) > 0) || !std::isfinite(norm(forward))) {
    throw InputError("camera: the eye is at the target (or not finite)");
  }
  if (!(norm(cross(normalized(forward), normalized(c.up))) > 1e-6)) {
    throw InputError("camera: the up direction is along the view (or zero)");
  }
  if (!(c.fov_deg > 0 && c.fov_deg < 180)) {
    throw InputError(
        fmt::format("camera: field of view must be in (0, 180) degrees (got {})", c.fov_deg));
  }
}

// The mesh in an Embree scene, with area-weighted vertex normals for smooth shading (or normals
// per corner, when edges sharper than a crease angle stay sharp).
class MeshShader::Scene {
 public:
  Scene(const TriangleMesh& mesh, double crease_deg) : mesh_(mesh) {
    device_.reset(rtcNewDevice(nullptr));
    if (!device_) throw Error("render: Embree device creation failed");
    scene_.reset(rtcNewScene(device_.get()));
    // Watertight ray-triangle tests: no ray slips between two triangles of the closed mesh.
    rtcSetSceneFlags(scene_.get(), RTC_SCENE_FLAG_ROBUST);
    RTCGeometry g = rtcNewGeometry(device_.get(), RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(
        g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), mesh.vertices.size()));
    auto* ib = static_cast<unsigned*>(
        rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned),
                                mesh.triangles.size()));
    if (vb == nullptr || ib == nullptr) {
      rtcReleaseGeometry(g);
      throw Error("render: Embree buffer allocation failed");
    }
    for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
      for (int c = 0; c < 3; ++c) vb[3 * v + c] = static_cast<float>(mesh.vertices[v][c]);
    }
    normals_.assign(mesh.vertices.size(), Vec{0, 0, 0});
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      const auto& tri = mesh.triangles[t];
      for (int c = 0; c < 3; ++c) ib[3 * t + c] = static_cast<unsigned>(tri[c]);
      const Vec n = face_normal(t);
      for (int c = 0; c < 3; ++c) {
        Vec& vn = normals_[static_cast<std::size_t>(tri[c])];
        vn = add(vn, n);
      }
    }
    for (Vec& n : normals_) n = normalized(n);
    if (crease_deg < 180) crease(crease_deg);
    rtcCommitGeometry(g);
    rtcAttachGeometry(scene_.get(), g);
    rtcReleaseGeometry(g);
    rtcCommitScene(scene_.get());
  }

  // Shade of the first hit along the ray (RGB in [0, 1]), or nothing.
  std::optional<Vec> trace(const Vec& org, const Vec& dir, const Vec& view_right,
                           const Vec& view_up) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit rh{};
    rh.ray.org_x = static_cast<float>(org[0]);
    rh.ray.org_y = static_cast<float>(org[1]);
    rh.ray.org_z = static_cast<float>(org[2]);
    rh.ray.dir_x = static_cast<float>(dir[0]);
    rh.ray.dir_y = static_cast<float>(dir[1]);
    rh.ray.dir_z = static_cast<float>(dir[2]);
    rh.ray.tnear = 0.0f;
    rh.ray.tfar = std::numeric_limits<float>::infinity();
    rh.ray.mask = 0xffffffffu;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene_.get(), &context, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;
    const auto& tri = mesh_.triangles[rh.hit.primID];
    const double u = rh.hit.u, v = rh.hit.v;
    const auto corner = [&](std::size_t c) -> const Vec& {
      return corners_.empty() ? normals_[static_cast<std::size_t>(tri[c])]
                              : corners_[3 * static_cast<std::size_t>(rh.hit.primID) + c];
    };
    Vec n =
        normalized(add(add(scale(corner(0), 1 - u - v), scale(corner(1), u)), scale(corner(2), v)));
    const bool back = dot(face_normal(rh.hit.primID), dir) > 0;
    if (back) n = scale(n, -1.0);
    // Lights fixed to the view: a key light from the upper left, a fill from the right.
    const Vec toward_eye = scale(dir, -1.0);
    const Vec key = normalized(add(add(scale(view_right, -0.5), scale(view_up, 0.8)), toward_eye));
    const Vec fill = normalized(add(scale(view_right, 0.8), toward_eye));
    const double diffuse = 0.75 * std::max(0.0, dot(n, key)) + 0.25 * std::max(0.0, dot(n, fill));
    const Vec half = normalized(add(key, toward_eye));
    const double specular = 0.25 * std::pow(std::max(0.0, dot(n, half)), 40.0);
    // Outside faces blue-grey; a face seen from behind (an open or inside-out mesh) in red.
    const Vec base = back ? Vec{0.85, 0.3, 0.25} : Vec{0.55, 0.64, 0.8};
    Vec c{};
    for (int k = 0; k < 3; ++k) c[k] = std::min(1.0, base[k] * (0.18 + 0.82 * diffuse) + specular);
    return c;
  }

 private:
  Vec face_normal(std::size_t t) const {
    const auto& tri = mesh_.triangles[t];
    const auto p = [&](int c) {
      const auto& v = mesh_.vertices[static_cast<std::size_t>(tri[c])];
      return Vec{v[0], v[1], v[2]};
    };
    return cross(sub(p(1), p(0)), sub(p(2), p(0)));
  }

  // A normal per corner: the area-weighted mean of the normals of the triangles at its vertex
  // that lie within crease_deg of its own triangle's (its own always among them).
  void crease(double crease_deg) {
    const std::size_t nt = mesh_.triangles.size();
    // The triangles at each vertex (compressed rows).
    std::vector<std::size_t> first(mesh_.vertices.size() + 1, 0), at(3 * nt);
    for (const auto& tri : mesh_.triangles) {
      for (const int v : tri) ++first[static_cast<std::size_t>(v) + 1];
    }
    for (std::size_t v = 0; v < mesh_.vertices.size(); ++v) first[v + 1] += first[v];
    std::vector<std::size_t> fill(first.begin(), first.end() - 1);
    std::vector<Vec> area(nt), unit(nt);
    for (std::size_t t = 0; t < nt; ++t) {
      area[t] = face_normal(t);
      unit[t] = normalized(area[t]);
      for (const int v : mesh_.triangles[t]) at[fill[static_cast<std::size_t>(v)]++] = t;
    }
    const double limit = std::cos(crease_deg * kPi / 180.0);
    corners_.assign(3 * nt, Vec{0, 0, 0});
    for (std::size_t t = 0; t < nt; ++t) {
      for (std::size_t c = 0; c < 3; ++c) {
        const auto v = static_cast<std::size_t>(mesh_.triangles[t][c]);
        Vec sum = area[t];
        for (std::size_t k = first[v]; k < first[v + 1]; ++k) {
          if (at[k] != t && dot(unit[at[k]], unit[t]) >= limit) sum = add(sum, area[at[k]]);
        }
        corners_[3 * t + c] = normalized(sum);
      }
    }
  }

  const TriangleMesh& mesh_;
  std::unique_ptr<RTCDeviceTy, DeviceDeleter> device_;
  std::unique_ptr<RTCSceneTy, SceneDeleter> scene_;
  std::vector<Vec> normals_;  // per vertex
  std::vector<Vec> corners_;  // per corner (3 a triangle), with a crease angle; else empty
};

MeshShader::MeshShader(const TriangleMesh& mesh, double crease_deg)
    : scene_(std::make_unique<Scene>(mesh, crease_deg)) {}

MeshShader::~MeshShader() = default;

void MeshShader::shade(const Camera& c, int width, int height, unsigned char* rgb,
                       std::size_t stride) const {
  const double aspect = static_cast<double>(width) / height;
  const Vec f = normalized(sub(c.target, c.eye));
  const Vec r = normalized(cross(f, c.up));
  const Vec u = cross(r, f);
  const double th = std::tan(0.5 * c.fov_deg * kPi / 180.0);
  tbb::parallel_for(tbb::blocked_range<int>(0, height), [&](const auto& rows) {
    for (int j = rows.begin(); j != rows.end(); ++j) {
      for (int i = 0; i < width; ++i) {
        Vec sum{0, 0, 0};
        for (int s = 0; s < 4; ++s) {  // 2x2 samples
          const double sx = (i + 0.25 + 0.5 * (s & 1)) / width;
          const double sy = (j + 0.25 + 0.5 * (s >> 1)) / height;
          const double x = (2 * sx - 1) * th * aspect, y = (1 - 2 * sy) * th;
          const Vec dir = normalized(add(f, add(scale(r, x), scale(u, y))));
          const std::optional<Vec> hit = scene_->trace(c.eye, dir, r, u);
          // Background: a soft vertical gradient.
          const double g = 0.97 - 0.12 * sy;
          sum = add(sum, hit ? *hit : Vec{g, g, g});
        }
        unsigned char* p =
            rgb + static_cast<std::size_t>(j) * stride + static_cast<std::size_t>(i) * 3;
        for (int ch = 0; ch < 3; ++ch) {
          p[ch] =
              static_cast<unsigned char>(std::lround(255.0 * std::clamp(sum[ch] / 4, 0.0, 1.0)));
        }
      }
    }
  });
}

}  // namespace fuzzycsg::render_detail
