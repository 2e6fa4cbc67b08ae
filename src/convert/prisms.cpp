// Prisms proposed from flat walls: a hole or pocket whose walls are planes parallel to one axis
// (the bowl of a P, a slanted slot) is the region on the far side of every wall, and a boss with
// such walls the region on the near side of every wall. Neither is a box when a wall is off the
// frame, and a chain of single half-spaces cannot carve a hole out of the middle of a part.

#include <algorithm>
#include <cmath>
#include <numeric>

#include "convert/candidates.hpp"
#include "convert/detect_internal.hpp"

namespace fuzzycsg::convert {

namespace {

using Polygon = std::vector<Eigen::Vector2d>;

// Union-find over surface indices.
class Groups {
 public:
  explicit Groups(std::size_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), 0); }
  int root(int i) {
    while (parent_[static_cast<std::size_t>(i)] != i) {
      parent_[static_cast<std::size_t>(i)] =
          parent_[static_cast<std::size_t>(parent_[static_cast<std::size_t>(i)])];
      i = parent_[static_cast<std::size_t>(i)];
    }
    return i;
  }
  void unite(int a, int b) {
    a = root(a);
    b = root(b);
    if (a != b) parent_[static_cast<std::size_t>(std::max(a, b))] = std::min(a, b);
  }
  // The groups of at least two members, each in increasing order, ordered by their first member.
  std::vector<std::vector<int>> members() {
    std::vector<std::vector<int>> by_root(parent_.size());
    for (std::size_t i = 0; i < parent_.size(); ++i) {
      by_root[static_cast<std::size_t>(root(static_cast<int>(i)))].push_back(static_cast<int>(i));
    }
    std::vector<std::vector<int>> out;
    for (auto& g : by_root) {
      if (g.size() >= 2) out.push_back(std::move(g));
    }
    return out;
  }

 private:
  std::vector<int> parent_;
};

// The part of a convex polygon where n . q <= d (Sutherland-Hodgman, one edge).
Polygon clip(const Polygon& polygon, const Eigen::Vector2d& n, double d) {
  Polygon out;
  const std::size_t count = polygon.size();
  for (std::size_t i = 0; i < count; ++i) {
    const Eigen::Vector2d& a = polygon[i];
    const Eigen::Vector2d& b = polygon[(i + 1) % count];
    const double fa = n.dot(a) - d, fb = n.dot(b) - d;
    if (fa <= 0) out.push_back(a);
    if ((fa < 0 && fb > 0) || (fa > 0 && fb < 0)) out.push_back(a + fa / (fa - fb) * (b - a));
  }
  return out;
}

double area(const Polygon& polygon) {
  double twice = 0;
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    const Eigen::Vector2d& a = polygon[i];
    const Eigen::Vector2d& b = polygon[(i + 1) % polygon.size()];
    twice += a.x() * b.y() - b.x() * a.y();
  }
  return 0.5 * twice;
}

// Consecutive vertices closer than `eps` merged.
Polygon without_repeats(const Polygon& polygon, double eps) {
  Polygon out;
  for (const Eigen::Vector2d& v : polygon) {
    if (out.empty() || (v - out.back()).norm() > eps) out.push_back(v);
  }
  while (out.size() > 1 && (out.front() - out.back()).norm() <= eps) out.pop_back();
  return out;
}

// A connected piece of one plane: triangles of the surface joined across the mesh's edges.
// Coplanar faces far apart are one surface (detect.hpp) but different patches: the face of a
// hole's wall and a face of the outline in the same plane.
struct Patch {
  int surface = -1;
  std::vector<int> triangles;
};

std::vector<Patch> plane_patches(const detail::PreparedMesh& m,
                                 const std::vector<Surface>& surfaces, std::vector<int>& patch_of) {
  std::vector<int> owner(m.areas.size(), -1);
  for (std::size_t i = 0; i < surfaces.size(); ++i) {
    if (surfaces[i].kind != SurfaceKind::kPlane) continue;
    for (const int t : surfaces[i].triangles)
      owner[static_cast<std::size_t>(t)] = static_cast<int>(i);
  }
  patch_of.assign(m.areas.size(), -1);
  std::vector<Patch> patches;
  for (const int start : m.valid) {
    const int surface = owner[static_cast<std::size_t>(start)];
    if (surface < 0 || patch_of[static_cast<std::size_t>(start)] >= 0) continue;
    const int index = static_cast<int>(patches.size());
    Patch patch{surface, {}};
    std::vector<int> stack{start};
    patch_of[static_cast<std::size_t>(start)] = index;
    while (!stack.empty()) {
      const int t = stack.back();
      stack.pop_back();
      patch.triangles.push_back(t);
      for (const int u : m.neighbours[static_cast<std::size_t>(t)]) {
        if (u < 0 || owner[static_cast<std::size_t>(u)] != surface ||
            patch_of[static_cast<std::size_t>(u)] >= 0) {
          continue;
        }
        patch_of[static_cast<std::size_t>(u)] = index;
        stack.push_back(u);
      }
    }
    std::sort(patch.triangles.begin(), patch.triangles.end());
    patches.push_back(std::move(patch));
  }
  return patches;
}

// Wall patches (parallel to the axis) that meet at the mesh's edges: joined into `concave`
// groups where the solid turns in at the edge (a hole's corner) and `convex` ones where it turns
// out.
void join_walls(const detail::PreparedMesh& m, const std::vector<int>& patch_of,
                const std::vector<bool>& wall, Groups& concave, Groups& convex) {
  const double eps = 1e-9 * m.diagonal;
  for (const int t : m.valid) {
    for (const int u : m.neighbours[static_cast<std::size_t>(t)]) {
      if (u < 0 || u < t) continue;
      const int a = patch_of[static_cast<std::size_t>(t)],
                b = patch_of[static_cast<std::size_t>(u)];
      if (a < 0 || b < 0 || a == b) continue;
      if (!wall[static_cast<std::size_t>(a)] || !wall[static_cast<std::size_t>(b)]) continue;
      // The neighbour's centroid above this triangle's plane: the solid turns in at the edge.
      const double rise = m.normals[static_cast<std::size_t>(t)].dot(
          m.centroids[static_cast<std::size_t>(u)] - m.centroids[static_cast<std::size_t>(t)]);
      if (rise > eps) concave.unite(a, b);
      if (rise < -eps) convex.unite(a, b);
    }
  }
}

}  // namespace

void prism_solids(const std::vector<Surface>& surfaces, const TriangleMesh& mesh,
                  const Eigen::Matrix3d& frame, const Eigen::AlignedBox3d& bounds, double margin,
                  double cos_tol, std::vector<Solid>& out) {
  const detail::PreparedMesh m = detail::prepare_mesh(mesh);
  std::vector<int> patch_of;
  const std::vector<Patch> patches = plane_patches(m, surfaces, patch_of);
  const double sin_tol = std::sqrt(std::max(0.0, 1.0 - cos_tol * cos_tol));
  const Eigen::AlignedBox3d grown(bounds.min().array() - margin, bounds.max().array() + margin);
  const double size = bounds.sizes().maxCoeff();
  for (int a = 0; a < 3; ++a) {
    const Eigen::Vector3d axis = frame.col(a);
    std::vector<bool> wall(patches.size(), false), oblique(patches.size(), false);
    for (std::size_t i = 0; i < patches.size(); ++i) {
      const Eigen::Vector3d n = surfaces[static_cast<std::size_t>(patches[i].surface)].direction;
      if (std::abs(n.dot(axis)) > sin_tol) continue;
      wall[i] = true;
      oblique[i] = std::abs(n.dot(frame.col((a + 1) % 3))) < cos_tol &&
                   std::abs(n.dot(frame.col((a + 2) % 3))) < cos_tol;
    }
    Groups concave(patches.size()), convex(patches.size());
    join_walls(m, patch_of, wall, concave, convex);
    // The prism's frame: z along the axis; the polygon in its xy plane, the centre on the axis.
    const Eigen::Matrix3d rotation = rotation_with_z(axis);
    Polygon rectangle;
    {
      Eigen::AlignedBox2d box;
      for (int c = 0; c < 8; ++c) {
        const Eigen::Vector3d corner =
            frame * grown.corner(static_cast<Eigen::AlignedBox3d::CornerType>(c));
        box.extend((rotation.transpose() * corner).head<2>());
      }
      rectangle = {
          box.min(), {box.max().x(), box.min().y()}, box.max(), {box.min().x(), box.max().y()}};
    }
    for (const bool hole : {true, false}) {
      for (const std::vector<int>& group : (hole ? concave : convex).members()) {
        // Boxes of the frame cover walls on its axes; a boss with one wall off them is a box
        // cut by a half-space, which the chain builds as well.
        const auto off_frame = std::count_if(group.begin(), group.end(), [&](int i) {
          return oblique[static_cast<std::size_t>(i)];
        });
        if (off_frame < (hole ? 1 : 2)) continue;
        Polygon polygon = rectangle;
        double lo = std::numeric_limits<double>::infinity(), hi = -lo;
        for (const int i : group) {
          const Surface& s =
              surfaces[static_cast<std::size_t>(patches[static_cast<std::size_t>(i)].surface)];
          const Eigen::Vector3d local = rotation.transpose() * s.direction;
          const double length = local.head<2>().norm();
          const Eigen::Vector2d n = local.head<2>() / length;
          const double d = s.direction.dot(s.point) / length;
          // A hole lies beyond every wall (n . q >= d), a boss behind every wall.
          polygon = hole ? clip(polygon, -n, -d) : clip(polygon, n, d);
          for (const int t : patches[static_cast<std::size_t>(i)].triangles) {
            for (const int v : mesh.triangles[static_cast<std::size_t>(t)]) {
              const auto& p = mesh.vertices[static_cast<std::size_t>(v)];
              const double z = axis.dot(Eigen::Vector3d(p[0], p[1], p[2]));
              lo = std::min(lo, z);
              hi = std::max(hi, z);
            }
          }
        }
        polygon = without_repeats(polygon, 1e-9 * size);
        if (polygon.size() < 3 || area(polygon) < 1e-4 * size * size) continue;
        for (const auto& [z0, z1] :
             {std::pair{lo, hi}, std::pair{grown.min()[a], grown.max()[a]}}) {
          if (z1 - z0 <= 1e-6 * size) continue;
          Solid prism;
          prism.kind = SolidKind::kPrism;
          prism.rotation = rotation;
          prism.centre = 0.5 * (z0 + z1) * axis;
          prism.size = {0, 0, z1 - z0};
          prism.polygon = polygon;
          out.push_back(prism);
        }
      }
    }
  }
}

}  // namespace fuzzycsg::convert
