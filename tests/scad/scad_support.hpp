#pragma once
// Helpers of the scad tests: quadrics built from canonical forms, and OpenSCAD's output read
// back (STL through assimp, SVG paths by hand) with inside tests for sampled points.

#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <assimp/Importer.hpp>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <span>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include "fuzzycsg/core/tree.hpp"
#include "fuzzycsg/eval/evaluator.hpp"
#include "fuzzycsg/mesh/mesh.hpp"

namespace fuzzycsg::scad_test {

// q(x) = s * g(W (x - c)) with W = (R diag(axes))^-1 and g(v) = v^T G v + h^T v + k0, as the 10
// coefficients of the tree format.
inline std::vector<double> make_quadric3(const Eigen::Matrix3d& g, const Eigen::Vector3d& h,
                                         double k0, const Eigen::Matrix3d& r,
                                         const Eigen::Vector3d& axes, const Eigen::Vector3d& c,
                                         double s) {
  const Eigen::Matrix3d w = (r * axes.asDiagonal()).inverse();
  const Eigen::Matrix3d a = s * (w.transpose() * g * w);
  const Eigen::Vector3d b = -2.0 * a * c + s * (w.transpose() * h);
  const double k = c.dot(a * c) - s * h.dot(w * c) + s * k0;
  return {a(0, 0), a(1, 1), a(2, 2), 2 * a(0, 1), 2 * a(1, 2), 2 * a(0, 2), b[0], b[1], b[2], k};
}

inline std::vector<double> make_quadric2(const Eigen::Matrix2d& g, const Eigen::Vector2d& h,
                                         double k0, double angle_rad, const Eigen::Vector2d& axes,
                                         const Eigen::Vector2d& c, double s) {
  const Eigen::Matrix2d r = Eigen::Rotation2Dd(angle_rad).toRotationMatrix();
  const Eigen::Matrix2d w = (r * axes.asDiagonal()).inverse();
  const Eigen::Matrix2d a = s * (w.transpose() * g * w);
  const Eigen::Vector2d b = -2.0 * a * c + s * (w.transpose() * h);
  const double k = c.dot(a * c) - s * h.dot(w * c) + s * k0;
  return {a(0, 0), a(1, 1), 2 * a(0, 1), b[0], b[1], k};
}

inline double quadric_value(std::span<const double> q, const double* x) {
  if (q.size() == 10) {
    return q[0] * x[0] * x[0] + q[1] * x[1] * x[1] + q[2] * x[2] * x[2] + q[3] * x[0] * x[1] +
           q[4] * x[1] * x[2] + q[5] * x[2] * x[0] + q[6] * x[0] + q[7] * x[1] + q[8] * x[2] + q[9];
  }
  return q[0] * x[0] * x[0] + q[1] * x[1] * x[1] + q[2] * x[0] * x[1] + q[3] * x[0] + q[4] * x[1] +
         q[5];
}

inline Eigen::Matrix3d random_rotation(std::mt19937_64& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::Quaterniond q(n(rng), n(rng), n(rng), n(rng));
  q.normalize();
  return q.toRotationMatrix();
}

// A tree file's text for a given root (JSON), 3D or 2D, default domain.
inline std::string tree_text(int dim, const std::string& root) {
  return R"({"format": "fuzzycsg-tree", "version": 1, "dim": )" + std::to_string(dim) +
         R"(, "root": )" + root + "}";
}

inline std::string json_numbers(std::span<const double> v) {
  std::ostringstream s;
  s.precision(17);
  s << "[";
  for (std::size_t i = 0; i < v.size(); ++i) s << (i ? ", " : "") << v[i];
  s << "]";
  return s.str();
}

// ---------------------------------------------------------------------------------------------
// OpenSCAD

inline bool have_openscad() {
  static const bool found = std::system("command -v openscad > /dev/null 2>&1") == 0;
  return found;
}

#define FUZZYCSG_REQUIRE_OPENSCAD()                                                            \
  do {                                                                                         \
    if (!::fuzzycsg::scad_test::have_openscad()) {                                             \
      GTEST_SKIP() << "openscad is not installed (scripts/install-deps.sh installs it); this " \
                      "test renders the exported file with it";                                \
    }                                                                                          \
  } while (0)

// A fresh directory for one test's files, removed with it unless the test failed.
class TestDir {
 public:
  explicit TestDir(const std::string& name)
      : path_(std::filesystem::temp_directory_path() /
              ("fuzzycsg-scad-" + name + "-" + std::to_string(::getpid()))) {
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TestDir() {
    std::error_code ignored;
    if (!::testing::Test::HasFailure()) std::filesystem::remove_all(path_, ignored);
  }
  TestDir(const TestDir&) = delete;
  TestDir& operator=(const TestDir&) = delete;
  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

 private:
  std::filesystem::path path_;
};

// Runs `openscad -o out in`; returns its exit status, and its messages in `log`.
inline int run_openscad(const std::filesystem::path& in, const std::filesystem::path& out,
                        std::string* log = nullptr) {
  const std::filesystem::path log_path = out.string() + ".log";
  const std::string cmd = "timeout 600 openscad -o '" + out.string() + "' '" + in.string() +
                          "' > '" + log_path.string() + "' 2>&1";
  const int rc = std::system(cmd.c_str());
  if (log) {
    std::ifstream f(log_path);
    std::stringstream ss;
    ss << f.rdbuf();
    *log = ss.str();
  }
  return rc;
}

inline TriangleMesh read_stl(const std::filesystem::path& path) {
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(path.string(), aiProcess_JoinIdenticalVertices);
  TriangleMesh m;
  if (scene == nullptr) return m;
  for (unsigned i = 0; i < scene->mNumMeshes; ++i) {
    const aiMesh* mesh = scene->mMeshes[i];
    const int base = static_cast<int>(m.vertices.size());
    for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
      m.vertices.push_back({mesh->mVertices[v].x, mesh->mVertices[v].y, mesh->mVertices[v].z});
    }
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
      const aiFace& face = mesh->mFaces[f];
      if (face.mNumIndices != 3) continue;
      m.triangles.push_back({base + static_cast<int>(face.mIndices[0]),
                             base + static_cast<int>(face.mIndices[1]),
                             base + static_cast<int>(face.mIndices[2])});
    }
  }
  return m;
}

// Inside a closed triangle mesh by the parity of the crossings of a ray along +x.
inline bool inside_mesh(const TriangleMesh& m, const std::array<double, 3>& p) {
  int crossings = 0;
  for (const auto& t : m.triangles) {
    const auto& a = m.vertices[static_cast<std::size_t>(t[0])];
    const auto& b = m.vertices[static_cast<std::size_t>(t[1])];
    const auto& c = m.vertices[static_cast<std::size_t>(t[2])];
    // Barycentric coordinates of (p.y, p.z) in the triangle projected on the yz plane.
    const double d = (b[1] - a[1]) * (c[2] - a[2]) - (c[1] - a[1]) * (b[2] - a[2]);
    if (d == 0) continue;
    const double u = ((p[1] - a[1]) * (c[2] - a[2]) - (c[1] - a[1]) * (p[2] - a[2])) / d;
    const double v = ((b[1] - a[1]) * (p[2] - a[2]) - (p[1] - a[1]) * (b[2] - a[2])) / d;
    if (u < 0 || v < 0 || u + v > 1) continue;
    const double x = a[0] + u * (b[0] - a[0]) + v * (c[0] - a[0]);
    if (x > p[0]) ++crossings;
  }
  return crossings % 2 == 1;
}

// The loops of the paths of an SVG file that OpenSCAD wrote ("M x,y L x,y ... z"), with y
// turned back up (OpenSCAD writes -y).
inline std::vector<std::vector<std::array<double, 2>>> read_svg_loops(
    const std::filesystem::path& path) {
  std::ifstream f(path);
  std::stringstream ss;
  ss << f.rdbuf();
  const std::string text = ss.str();
  std::vector<std::vector<std::array<double, 2>>> loops;
  std::size_t at = 0;
  while ((at = text.find(" d=\"", at)) != std::string::npos) {
    at += 4;
    const std::size_t end = text.find('"', at);
    std::string d = text.substr(at, end - at);
    for (char& ch : d) {
      if (ch == ',') ch = ' ';
    }
    std::istringstream in(d);
    std::string tok;
    std::vector<std::array<double, 2>> loop;
    while (in >> tok) {
      if (tok == "M" || tok == "L") {
        double x = 0, y = 0;
        in >> x >> y;
        if (tok == "M" && !loop.empty()) loops.push_back(std::move(loop)), loop.clear();
        loop.push_back({x, -y});
      } else if (tok == "z" || tok == "Z") {
        if (!loop.empty()) loops.push_back(std::move(loop)), loop.clear();
      }
    }
    if (!loop.empty()) loops.push_back(std::move(loop));
    at = end;
  }
  return loops;
}

inline bool inside_loops(const std::vector<std::vector<std::array<double, 2>>>& loops, double px,
                         double py) {
  bool inside = false;
  for (const auto& loop : loops) {
    for (std::size_t i = 0, j = loop.size() - 1; i < loop.size(); j = i++) {
      const auto& a = loop[j];
      const auto& b = loop[i];
      if ((a[1] > py) != (b[1] > py) && px < a[0] + (py - a[1]) * (b[0] - a[0]) / (b[1] - a[1])) {
        inside = !inside;
      }
    }
  }
  return inside;
}

// Area of the even-odd region of the loops: a loop inside an odd number of others is a hole.
inline double loops_area(const std::vector<std::vector<std::array<double, 2>>>& loops) {
  double total = 0.0;
  for (std::size_t k = 0; k < loops.size(); ++k) {
    double a = 0.0;
    const auto& loop = loops[k];
    for (std::size_t i = 0, j = loop.size() - 1; i < loop.size(); j = i++) {
      a += loop[j][0] * loop[i][1] - loop[i][0] * loop[j][1];
    }
    int depth = 0;
    for (std::size_t o = 0; o < loops.size(); ++o) {
      if (o != k && inside_loops({loops[o]}, loop[0][0], loop[0][1])) ++depth;
    }
    total += (depth % 2 == 0 ? 0.5 : -0.5) * std::abs(a);
  }
  return total;
}

// Uniform samples of the domain: where `inside` agrees with the tree (occupancy > 0.5 by the
// reference evaluator), and the intersection over union of the two insides.
struct Agreement {
  double fraction = 0.0;  // of all samples
  double iou = 0.0;       // samples inside both / inside either
};

template <class Inside>
Agreement agreement(const Tree& tree, int samples, Inside inside, std::uint64_t seed = 7) {
  const Domain d = tree.domain_or_default();
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const std::vector<double> params = tree.params.values();
  int agree = 0, both = 0, either = 0;
  for (int s = 0; s < samples; ++s) {
    std::array<double, 3> p{0, 0, 0};
    for (int i = 0; i < tree.dim; ++i) {
      p[static_cast<std::size_t>(i)] =
          d.min[static_cast<std::size_t>(i)] +
          u(rng) * (d.max[static_cast<std::size_t>(i)] - d.min[static_cast<std::size_t>(i)]);
    }
    const bool ours = reference_occupancy(tree, params, p.data()) > 0.5;
    const bool theirs = inside(p);
    agree += ours == theirs ? 1 : 0;
    both += ours && theirs ? 1 : 0;
    either += ours || theirs ? 1 : 0;
  }
  return {static_cast<double>(agree) / samples,
          either > 0 ? static_cast<double>(both) / either : 1.0};
}

}  // namespace fuzzycsg::scad_test
