#include "fuzzycsg/render/render.hpp"

#include <embree3/rtcore.h>
#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <vector>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/eval/evaluator.hpp"
#include "fuzzycsg/io/png.hpp"

namespace fuzzycsg {

namespace {

using Vec = std::array<double, 3>;
constexpr double kPi = 3.14159265358979323846;

Vec sub(const Vec& a, const Vec& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Vec add(const Vec& a, const Vec& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
Vec scale(const Vec& a, double s) { return {a[0] * s, a[1] * s, a[2] * s}; }
double dot(const Vec& a, const Vec& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec cross(const Vec& a, const Vec& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double norm(const Vec& a) { return std::sqrt(dot(a, a)); }
Vec normalized(const Vec& a) {
  const double n = norm(a);
  return n > 0 ? scale(a, 1.0 / n) : a;
}

struct DeviceDeleter {
  void operator()(RTCDevice d) const { rtcReleaseDevice(d); }
};
struct SceneDeleter {
  void operator()(RTCScene s) const { rtcReleaseScene(s); }
};

// The mesh in an Embree scene, with area-weighted vertex normals for smooth shading.
class RayScene {
 public:
  explicit RayScene(const TriangleMesh& mesh) : mesh_(mesh) {
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
    Vec n = normalized(add(add(scale(normals_[static_cast<std::size_t>(tri[0])], 1 - u - v),
                               scale(normals_[static_cast<std::size_t>(tri[1])], u)),
                           scale(normals_[static_cast<std::size_t>(tri[2])], v)));
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

  const TriangleMesh& mesh_;
  std::unique_ptr<RTCDeviceTy, DeviceDeleter> device_;
  std::unique_ptr<RTCSceneTy, SceneDeleter> scene_;
  std::vector<Vec> normals_;
};

void check_camera(const Camera& c, const Tree& tree, std::span<const double> params) {
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
  const double eye[3] = {c.eye[0], c.eye[1], c.eye[2]};
  if (reference_occupancy(tree, params, eye) >= 0.5) {
    throw InputError(fmt::format("camera: the eye ({:g}, {:g}, {:g}) is inside the shape", c.eye[0],
                                 c.eye[1], c.eye[2]));
  }
}

}  // namespace

Camera framing_camera(const TriangleMesh& mesh, double azimuth_deg, double elevation_deg,
                      const std::array<double, 3>& up, double aspect, double fov_deg) {
  const auto [lo, hi] = bounding_box(mesh);
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
  if (o.width < 1 || o.width > 8192 || o.height < 1 || o.height > 8192) {
    throw InputError(
        fmt::format("size must be 1..8192 pixels a side (got {}x{})", o.width, o.height));
  }
  if (o.views < 1 || o.views > 8) {
    throw InputError(fmt::format("views must be 1..8 (got {})", o.views));
  }
  const auto run = [&] {
    MeshOptions mo;
    mo.resolution = o.resolution;
    mo.threads = o.threads;
    const TriangleMesh mesh = extract_mesh(tree, params, mo);
    if (mesh.triangles.empty()) {
      throw InputError("render: the 0.5 level set is empty in the domain");
    }
    const RayScene scene(mesh);
    const double aspect = static_cast<double>(o.width) / o.height;
    std::vector<Camera> cameras;
    if (o.camera) {
      cameras.push_back(*o.camera);
    } else {
      for (int k = 0; k < o.views; ++k) {
        cameras.push_back(framing_camera(mesh, -55.0 + 360.0 * k / o.views, 25.0, o.up, aspect));
      }
    }
    for (const Camera& c : cameras) check_camera(c, tree, params);
    const int total_width = o.width * static_cast<int>(cameras.size());
    std::vector<unsigned char> px(static_cast<std::size_t>(total_width) * o.height * 3);
    for (std::size_t k = 0; k < cameras.size(); ++k) {
      const Camera& c = cameras[k];
      const Vec f = normalized(sub(c.target, c.eye));
      const Vec r = normalized(cross(f, c.up));
      const Vec u = cross(r, f);
      const double th = std::tan(0.5 * c.fov_deg * kPi / 180.0);
      tbb::parallel_for(tbb::blocked_range<int>(0, o.height), [&](const auto& rows) {
        for (int j = rows.begin(); j != rows.end(); ++j) {
          for (int i = 0; i < o.width; ++i) {
            Vec sum{0, 0, 0};
            for (int s = 0; s < 4; ++s) {  // 2x2 samples
              const double sx = (i + 0.25 + 0.5 * (s & 1)) / o.width;
              const double sy = (j + 0.25 + 0.5 * (s >> 1)) / o.height;
              const double x = (2 * sx - 1) * th * aspect, y = (1 - 2 * sy) * th;
              const Vec dir = normalized(add(f, add(scale(r, x), scale(u, y))));
              const std::optional<Vec> hit = scene.trace(c.eye, dir, r, u);
              // Background: a soft vertical gradient.
              const double g = 0.97 - 0.12 * sy;
              sum = add(sum, hit ? *hit : Vec{g, g, g});
            }
            unsigned char* p =
                px.data() + (static_cast<std::size_t>(j) * total_width +
                             static_cast<std::size_t>(k) * o.width + static_cast<std::size_t>(i)) *
                                3;
            for (int ch = 0; ch < 3; ++ch) {
              p[ch] = static_cast<unsigned char>(
                  std::lround(255.0 * std::clamp(sum[ch] / 4, 0.0, 1.0)));
            }
          }
        }
      });
    }
    return encode_png(total_width, o.height, 3, px);
  };
  if (o.threads > 0) {
    tbb::task_arena arena(o.threads);
    return arena.execute(run);
  }
  return run();
}

}  // namespace fuzzycsg
