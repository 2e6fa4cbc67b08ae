// CSG visibility by rays: exact on boxes (their meshes are the shapes) against the crisp
// evaluator along the same rays, the depth and normal of a cavity, a sphere's silhouette, and
// the errors for trees the mesh renderer cannot draw.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>
#include <numbers>
#include <random>
#include <set>
#include <string>

#include "diffcsg/visibility_reference.hpp"
#include "fuzzycsg/core/bezier.hpp"
#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/diffcsg/openscad_csg.hpp"
#include "fuzzycsg/diffcsg/visibility.hpp"
#include "fuzzycsg/eval/evaluator.hpp"
#include "fuzzycsg/io/tree_json.hpp"

namespace fuzzycsg::diffcsg {
namespace {

std::string numbers(std::initializer_list<double> v) {
  std::string s = "[";
  for (const double x : v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%s%.17g", s.size() > 1 ? ", " : "", x);
    s += buf;
  }
  return s + "]";
}

std::string tree_file(const std::string& root) {
  return R"({"format": "fuzzycsg-tree", "version": 1, "dim": 3, "domain": {"min": [-3, -3, -3], "max": [3, 3, 3]}, "root": )" +
         root + "}";
}

// For every pixel, the distance along its ray to the first point inside the crisp tree
// (occupancy 1), sampled every `h` over [near, far]; -1 where there is none.
std::vector<double> march(const Tree& tree, const Camera& cam, double h, double near, double far) {
  const int steps = static_cast<int>((far - near) / h);
  const std::size_t pixels = static_cast<std::size_t>(cam.width) * cam.height;
  std::vector<float> points(pixels * static_cast<std::size_t>(steps) * 3);
  for (int j = 0; j < cam.height; ++j) {
    for (int i = 0; i < cam.width; ++i) {
      const Vec3 d = cam.ray(i, j);
      const std::size_t px = static_cast<std::size_t>(j) * cam.width + i;
      for (int s = 0; s < steps; ++s) {
        const double t = near + s * h;
        float* p = &points[(px * static_cast<std::size_t>(steps) + s) * 3];
        for (int k = 0; k < 3; ++k) p[k] = static_cast<float>(cam.eye[k] + t * d[k]);
      }
    }
  }
  std::vector<float> occ(pixels * static_cast<std::size_t>(steps));
  Evaluator(tree).forward(tree.params.values(), points, occ);
  std::vector<double> first(pixels, -1);
  for (std::size_t px = 0; px < pixels; ++px) {
    for (int s = 0; s < steps; ++s) {
      if (occ[px * static_cast<std::size_t>(steps) + s] > 0.75f) {
        first[px] = near + s * h;
        break;
      }
    }
  }
  return first;
}

TEST(DiffcsgVisibility, UnitMeshesAreClosedWithOutwardNormals) {
  for (const PrimitiveMesh& unit :
       {unit_box(), unit_sphere(0), unit_sphere(2), unit_cylinder(16)}) {
    const TriangleMesh& m = unit.mesh;
    for (const auto& t : m.triangles) {
      const Vec3& a = m.vertices[static_cast<std::size_t>(t[0])];
      const Vec3& b = m.vertices[static_cast<std::size_t>(t[1])];
      const Vec3& c = m.vertices[static_cast<std::size_t>(t[2])];
      // Every face's normal points away from the centre (the shapes are convex).
      const Vec3 u{b[0] - a[0], b[1] - a[1], b[2] - a[2]}, w{c[0] - a[0], c[1] - a[1], c[2] - a[2]};
      const Vec3 n{u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
      EXPECT_GT(
          n[0] * (a[0] + b[0] + c[0]) + n[1] * (a[1] + b[1] + c[1]) + n[2] * (a[2] + b[2] + c[2]),
          0);
    }
    EXPECT_GT(signed_volume(m), 0);
  }
  EXPECT_EQ(unit_sphere(2).mesh.triangles.size(), 320u);
  EXPECT_EQ(unit_cylinder(16).mesh.triangles.size(), 64u);
}

TEST(DiffcsgVisibility, ExtrudesAndConesAreClosedWithTheirVolumes) {
  // A rounded slot (straight sides, semicircle-like Bézier ends), counter-clockwise and
  // clockwise, and a cone with an apex.
  const std::string slot =
      R"([[-0.5, -0.3], [-0.1, -0.3], [0.1, -0.3], [0.5, -0.3], [0.9, -0.3], [0.9, 0.3],
          [0.5, 0.3], [0.1, 0.3], [-0.1, 0.3], [-0.5, 0.3], [-0.9, 0.3], [-0.9, -0.3]])";
  std::string reversed = R"([[-0.5, -0.3], [-0.9, -0.3], [-0.9, 0.3], [-0.5, 0.3], [-0.1, 0.3],
      [0.1, 0.3], [0.5, 0.3], [0.9, 0.3], [0.9, -0.3], [0.5, -0.3], [0.1, -0.3], [-0.1, -0.3]])";
  for (const std::string& profile : {slot, reversed}) {
    const Tree tree = io::read_tree_string(
        R"({"format": "fuzzycsg-tree", "version": 1, "dim": 3, "root": {"type": "extrude",
        "profile": )" +
        profile + R"(, "height": 0.5}})");
    const Scene scene = scene_from_tree(tree, "slot");
    const TriangleMesh& m = scene.primitives[0].mesh;
    const std::vector<int>& smoothing = scene.primitives[0].smoothing;
    // Closed: every edge in exactly two triangles, once each way.
    std::map<std::pair<int, int>, int> edges;
    for (const auto& t : m.triangles) {
      for (int k = 0; k < 3; ++k)
        ++edges[{t[static_cast<std::size_t>(k)], t[static_cast<std::size_t>((k + 1) % 3)]}];
    }
    for (const auto& [e, n] : edges) {
      EXPECT_EQ(n, 1);
      EXPECT_EQ(edges.count({e.second, e.first}), 1u);
    }
    // The prism over the sampled polygon: its area times the height, outward.
    const Node& leaf = tree.node(tree.root);
    std::vector<double> control;
    for (std::size_t k = 0; k + 1 < leaf.intrinsic.size(); ++k) {
      control.push_back(tree.params[leaf.intrinsic[k]].value);
    }
    const std::vector<double> poly = bezier_profile(control);
    double area = 0;
    for (std::size_t q = 0; q < poly.size() / 2; ++q) {
      const std::size_t r = (q + 1) % (poly.size() / 2);
      area += (poly[2 * q] * poly[2 * r + 1] - poly[2 * r] * poly[2 * q + 1]) / 2;
    }
    EXPECT_NEAR(signed_volume(m), std::abs(area) * 0.5, 1e-12);
    // The ends meet the sides tangentially: one smooth wall (and -1, the flat caps).
    std::set<int> groups(smoothing.begin(), smoothing.end());
    EXPECT_EQ(groups.size(), 2u);
  }
  // A D: its straight back meets the sides at right angles and the sides turn by 31 degrees
  // into the curved front: four creases, four wall groups (and the caps).
  const Tree d = io::read_tree_string(
      R"({"format": "fuzzycsg-tree", "version": 1, "dim": 3, "root": {"type": "extrude",
      "profile": [[-0.6, -0.5], [-0.2, -0.5], [0.2, -0.5], [0.5, -0.5], [0.9, -0.3],
                  [0.9, 0.3], [0.5, 0.5], [0.2, 0.5], [-0.2, 0.5], [-0.6, 0.5], [-0.6, 0.2],
                  [-0.6, -0.2]], "height": 0.4}})");
  const Scene ds = scene_from_tree(d, "d");
  const std::vector<int>& dm = ds.primitives[0].smoothing;
  EXPECT_EQ(std::set<int>(dm.begin(), dm.end()).size(), 5u);
  const Tree cone = io::read_tree_string(
      R"({"format": "fuzzycsg-tree", "version": 1, "dim": 3, "root": {"type": "cone",
      "radius1": 0.5, "radius2": 0, "height": 1}})");
  const Scene s = scene_from_tree(cone, "cone");
  // A 16-sided pyramid: base area 16/2 sin(2 pi/16) r^2, times h / 3.
  EXPECT_NEAR(signed_volume(s.primitives[0].mesh),
              8 * std::sin(2 * 3.14159265358979 / 16) * 0.25 / 3, 1e-12);
  EXPECT_EQ(s.primitives[0].mesh.vertices.size(), 16u + 1 + 1);  // the ring, its centre, the apex
  // A self-intersecting profile is refused naming the node.
  try {
    scene_from_tree(io::read_tree_string(
                        R"({"format": "fuzzycsg-tree", "version": 1, "dim": 3, "root": {"op":
        "union", "children": [{"type": "sphere", "radius": 1}, {"type": "extrude", "profile":
        [[0, 0], [0.3, 0.3], [0.6, 0.6], [1, 1], [1, 0.6], [1, 0.3], [1, 0], [0.6, 0.3],
         [0.3, 0.6], [0, 1], [0, 0.6], [0, 0.3]], "height": 1}]}})"),
                    "bow.json");
    ADD_FAILURE() << "a bow tie was meshed";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bow.json: root.children[1]: profile"), std::string::npos)
        << e.what();
  }
}

TEST(DiffcsgVisibility, BoxTreesAgreeWithTheCrispEvaluatorAlongEveryRay) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0, 1);
  const char* ops[] = {"union", "intersection", "difference"};
  int trees = 0, drawn = 0;
  for (int k = 0; k < 6; ++k) {
    const auto leaf = [&] {
      return R"({"type": "box", "step": "crisp", "size": )" +
             numbers({0.6 + u(rng), 0.6 + u(rng), 0.6 + u(rng)}) + R"(, "translate": )" +
             numbers({u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5}) + R"(, "rotate": )" +
             numbers({90 * u(rng), 90 * u(rng), 90 * u(rng)}) + "}";
    };
    const auto op = [&](const std::string& a, const std::string& b) {
      return std::string(R"({"op": ")") + ops[rng() % 3] + R"(", "children": [)" + a + ", " + b +
             "]}";
    };
    const std::string text = tree_file(op(op(leaf(), leaf()), op(leaf(), leaf())));
    const Tree tree = io::read_tree_string(text);
    const Scene scene = scene_from_tree(tree, "random boxes");
    ASSERT_EQ(scene.triangle_count(), 48u);
    const Camera cam = Camera::orbit({0, 0, 0}, 30 + 40 * k, 25, 5, 32, 32, 40);
    const Frame f = render_visibility(scene, cam, 2);
    ++trees;
    int mismatches = 0;
    const double h = 4e-3;
    const std::vector<double> first = march(tree, cam, h, 2.5, 7.5);
    for (std::size_t px = 0; px < first.size(); ++px) {
      const bool seen = f.primitive[px] >= 0;
      if (seen != (first[px] >= 0) || (seen && std::abs(first[px] - f.depth[px]) > 2 * h)) {
        ++mismatches;
      }
    }
    if (f.visible_pixels() > 0) ++drawn;
    // Only rays that graze an edge within the marching step may disagree.
    EXPECT_LE(mismatches, f.width * f.height / 100) << text;
  }
  EXPECT_GE(drawn, 3) << "too few of the random trees are visible to test anything";
  EXPECT_EQ(trees, 6);
}

TEST(DiffcsgVisibility, ACavityShowsItsFarSideFacingTheCamera) {
  // A cube of side 2 less a ball of radius 0.6 centred on its face x = 1, seen along -x.
  const Tree tree = io::read_tree_string(tree_file(
      R"({"op": "difference", "children": [{"type": "box", "size": [2, 2, 2]},
          {"type": "sphere", "radius": 0.6, "translate": [1, 0, 0]}]})"));
  const Scene scene = scene_from_tree(tree, "cavity");
  const Camera cam = Camera::orbit({0, 0, 0}, 0, 0, 5, 65, 65, 30);
  const Frame f = render_visibility(scene, cam, 1);
  const std::size_t centre = 32 * 65 + 32;
  ASSERT_EQ(f.primitive[centre], 1) << "the ball's far side";
  // The ball's mesh is inscribed: its far side is at most 2% of r nearer the ball's centre.
  EXPECT_GE(f.depth[centre], 4.6 - 1e-4);
  EXPECT_LE(f.depth[centre], 4.6 + 0.02 * 0.6);
  EXPECT_GT(f.normal[centre][0], 0.95);  // facing the camera, into the ball
  // Off the cavity, the cube's face at depth 4.
  const std::size_t corner = 4 * 65 + 4;
  ASSERT_EQ(f.primitive[corner], 0);
  EXPECT_NEAR(f.depth[corner] * cam.ray(4, 4)[0] * -1, 4.0, 1e-4);
  EXPECT_NEAR(f.normal[corner][0], 1.0, 1e-6);
}

TEST(DiffcsgVisibility, ASpheresSilhouetteAndALens) {
  const auto sphere = [](double x) {
    return R"({"type": "sphere", "radius": 0.5, "translate": )" + numbers({x, 0, 0}) + "}";
  };
  const Camera cam = Camera::orbit({0, 0, 0}, 90, 0, 5, 128, 128, 30);  // from +y
  const Frame one = render_visibility(
      scene_from_tree(io::read_tree_string(tree_file(sphere(0))), "sphere"), cam, 2);
  const double angular = std::asin(0.5 / 5);
  const double radius_px = std::tan(angular) / std::tan(15 * std::numbers::pi / 180) * 64;
  const double area = std::numbers::pi * radius_px * radius_px;
  EXPECT_GT(one.visible_pixels(), 0.94 * area);
  EXPECT_LT(one.visible_pixels(), 1.01 * area);

  const std::string two = sphere(-0.3) + ", " + sphere(0.3);
  const Frame u = render_visibility(
      scene_from_tree(
          io::read_tree_string(tree_file(R"({"op": "union", "children": [)" + two + "]}")),
          "union"),
      cam, 2);
  const Frame lens = render_visibility(
      scene_from_tree(
          io::read_tree_string(tree_file(R"({"op": "intersection", "children": [)" + two + "]}")),
          "lens"),
      cam, 2);
  EXPECT_GT(u.visible_pixels(), one.visible_pixels());
  EXPECT_LT(lens.visible_pixels(), one.visible_pixels());
  EXPECT_GT(lens.visible_pixels(), 0);
}

TEST(DiffcsgVisibility, TreesItCannotDrawAreRefusedNamingTheNode) {
  const auto refused = [](const std::string& text, const std::string& expect) {
    try {
      scene_from_tree(io::read_tree_string(text), "model.json");
      ADD_FAILURE() << "accepted " << text;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(expect), std::string::npos) << e.what();
    }
  };
  refused(tree_file(R"({"op": "union", "children": [{"type": "sphere", "radius": 1},
      {"type": "torus", "major": 1, "minor": 0.2}]})"),
          "root.children[1]");
  refused(tree_file(R"({"op": "complement", "children": [{"type": "sphere", "radius": 1}]})"),
          "complement");
  refused(
      R"({"format": "fuzzycsg-tree", "version": 1, "dim": 2, "root": {"type": "circle", "radius": 1}})",
      "3D");
}

TEST(DiffcsgVisibility, OfCoplanarFacesTheOneThatBoundsTheSolidIsShown) {
  // A bar through a cube's bore; the bar's ends are coplanar with the bore's cylinder's caps
  // (z = +-1.5), which are no surface of the solid.
  const Scene scene = parse_openscad_csg(
      "union() { difference() { cube(size = [2, 2, 2], center = true);"
      " cylinder($fn = 29, h = 3, r = 0.6, center = true); }"
      " cube(size = [0.5, 0.5, 3], center = true); }",
      "bar");
  const Camera cam = Camera::orbit({0, 0, 0}, 30, 50, 9, 128, 128, 30);
  const Frame f = render_visibility(scene, cam, 2);
  int bar_top = 0, cylinder_cap = 0;
  for (int j = 0; j < f.height; ++j) {
    for (int i = 0; i < f.width; ++i) {
      const std::size_t px = static_cast<std::size_t>(j) * f.width + i;
      if (f.primitive[px] < 0) continue;
      const double z = cam.eye[2] + f.depth[px] * cam.ray(i, j)[2];
      if (std::abs(z - 1.5) > 1e-4) continue;
      bar_top += f.primitive[px] == 2;
      cylinder_cap += f.primitive[px] == 1;
    }
  }
  EXPECT_GT(bar_top, 20);
  EXPECT_EQ(cylinder_cap, 0);
}

// Bitwise equality of two frames (a float's every bit, so -0 and 0 differ).
template <class T>
int differing(const std::vector<T>& a, const std::vector<T>& b) {
  if (a.size() != b.size()) return -1;
  int n = 0;
  for (std::size_t k = 0; k < a.size(); ++k) n += std::memcmp(&a[k], &b[k], sizeof(T)) != 0;
  return n;
}

void expect_same_frame(const Frame& fast, const Frame& ref, const std::string& what) {
  EXPECT_EQ(fast.width, ref.width) << what;
  EXPECT_EQ(fast.height, ref.height) << what;
  // Ties are Embree's: a ray along a shared edge, or onto the coplanar faces of touching boxes,
  // is given to one triangle or primitive by code paths that differ between processors (on AMD
  // EPYC, 8 pixels of a frame of touching boxes). At most 0.5% of a frame's pixels may differ.
  const long long slack = static_cast<long long>(ref.width) * ref.height / 200;
  EXPECT_LE(differing(fast.primitive, ref.primitive), slack) << what << ": primitive";
  EXPECT_LE(differing(fast.triangle, ref.triangle), slack) << what << ": triangle";
  EXPECT_LE(differing(fast.depth, ref.depth), slack) << what << ": depth";
  EXPECT_LE(differing(fast.barycentric, ref.barycentric), slack) << what << ": barycentric";
  EXPECT_LE(differing(fast.normal, ref.normal), slack) << what << ": normal";
}

TEST(DiffcsgVisibility, CameraRaysAreTheFirstImplementations) {
  for (const Camera& cam : {Camera::orbit({0.1, 0.2, 0.3}, 37, 21, 4, 61, 47, 33),
                            Camera::orbit({0, 0, 0}, -120, -80, 9, 16, 100, 70)}) {
    for (int j = 0; j < cam.height; j += 3) {
      for (int i = 0; i < cam.width; i += 2) {
        const Vec3 a = cam.ray(i, j), b = reference::reference_ray(cam, i, j);
        ASSERT_EQ(std::memcmp(&a, &b, sizeof a), 0) << i << ", " << j;
      }
    }
  }
}

TEST(DiffcsgVisibility, TheFastRendererDrawsTheFirstImplementationsFramesToTheBit) {
  // Random trees of boxes, spheres and cylinders (some sharing faces), OpenSCAD's examples, from
  // cameras outside and inside the solids, at sizes that are not multiples of the packets'.
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0, 1);
  const char* ops[] = {"union", "intersection", "difference"};
  std::vector<std::pair<std::string, Scene>> scenes;
  for (int k = 0; k < 8; ++k) {
    const auto leaf = [&] {
      const int type = static_cast<int>(rng() % 3);
      // Every other tree on a grid of 1/4: coplanar faces, shared edges.
      const auto at = [&](double x) { return k % 2 ? std::round(4 * x) / 4 : x; };
      std::string placement =
          R"(, "translate": )" + numbers({at(u(rng) - 0.5), at(u(rng) - 0.5), at(u(rng) - 0.5)});
      if (k % 2 == 0) {
        placement += R"(, "rotate": )" + numbers({90 * u(rng), 90 * u(rng), 90 * u(rng)});
      }
      if (type == 0) {
        return R"({"type": "box", "size": )" +
               numbers({at(0.5 + u(rng)), at(0.5 + u(rng)), at(0.5 + u(rng))}) + placement + "}";
      }
      if (type == 1) {
        const std::string r = numbers({0.3 + 0.5 * u(rng)});
        return R"({"type": "sphere", "radius": )" + r.substr(1, r.size() - 2) + placement + "}";
      }
      return R"({"type": "cylinder", "radius": )" + std::to_string(at(0.25 + 0.5 * u(rng))) +
             R"(, "height": )" + std::to_string(at(0.5 + u(rng))) + placement + "}";
    };
    const auto op = [&](const std::string& a, const std::string& b) {
      return std::string(R"({"op": ")") + ops[rng() % 3] + R"(", "children": [)" + a + ", " + b +
             "]}";
    };
    const std::string text = tree_file(op(op(leaf(), leaf()), op(leaf(), op(leaf(), leaf()))));
    scenes.emplace_back(text, scene_from_tree(io::read_tree_string(text), "random"));
  }
  const std::filesystem::path scad = std::filesystem::path(FUZZYCSG_TEST_DATA_DIR) / "scad";
  for (const char* file :
       {"Old/example001.openscad.csg", "Old/example003.openscad.csg", "Basics/CSG.openscad.csg"}) {
    scenes.emplace_back(file, read_openscad_csg(scad / file));
  }
  // Axis-aligned boxes seen along the axes below: pixel-centre rays through mesh edges and
  // vertices, and faces seen edge on.
  const std::string box = R"({"type": "box", "size": [2, 2, 2]})";
  scenes.emplace_back(
      "cavity",
      scene_from_tree(io::read_tree_string(tree_file(
                          R"({"op": "difference", "children": [)" + box +
                          R"(, {"type": "sphere", "radius": 0.6, "translate": [1, 0, 0]}]})")),
                      "cavity"));
  scenes.emplace_back(
      "touching boxes",
      scene_from_tree(
          io::read_tree_string(tree_file(
              R"({"op": "union", "children": [{"type": "box", "size": [1, 2, 2], "translate": [-0.5, 0, 0]},
                 {"op": "difference", "children": [{"type": "box", "size": [1, 2, 2], "translate": [0.5, 0, 0]},
                 {"type": "box", "size": [1, 1, 1], "translate": [1, 0, 0.5]}]}]})")),
          "touching boxes"));
  int drawn = 0;
  for (const auto& [name, scene] : scenes) {
    double size = 0;
    for (const PrimitiveMesh& primitive : scene.primitives) {
      const TriangleMesh& m = primitive.mesh;
      for (const Vec3& v : m.vertices)
        size = std::max({size, std::abs(v[0]), std::abs(v[1]), std::abs(v[2])});
    }
    for (const Camera& cam :
         {Camera::orbit({0, 0, 0}, 360 * u(rng), 160 * u(rng) - 80, 2 + 3 * size, 61, 47, 40),
          // Closer in and narrower: the solid runs off the screen.
          Camera::orbit({0.1 * size, 0, 0}, 360 * u(rng), 30, 2 + 2 * size, 70, 50, 12),
          Camera::orbit({0, 0, 0}, 360 * u(rng), 20, 0.05 * size, 33, 38, 80),
          // Along an axis, odd sizes: the middle pixel's ray is the axis.
          Camera::orbit({0, 0, 0}, 90.0 * static_cast<double>(rng() % 4), 0, 2 + 3 * size, 65, 65,
                        30),
          Camera::orbit({0, 0, 0}, 45, 0, 2 + 3 * size, 33, 33, 30)}) {
      const Frame ref = reference::reference_visibility(scene, cam, 1);
      drawn += ref.visible_pixels() > 0;
      for (const int threads : {1, 2}) {
        expect_same_frame(render_visibility(scene, cam, threads), ref, name);
      }
    }
  }
  EXPECT_GE(drawn, 50) << "too few frames show anything";
}

}  // namespace
}  // namespace fuzzycsg::diffcsg
