// Mesh and contour files: OBJ, STL and PLY through assimp's exporters (to memory, then written
// atomically), SVG by hand (a few lines of text).
#include <assimp/scene.h>
#include <assimp/Exporter.hpp>
#include <assimp/Importer.hpp>

#include <fmt/format.h>
#include <algorithm>
#include <limits>
#include <memory>
#include <string>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/io/files.hpp"
#include "fuzzycsg/mesh/mesh.hpp"

namespace fuzzycsg {

namespace {

std::string lowercase_extension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

// One mesh of `faces` index lists (3 for triangles, 2 for line segments) in a scene assimp can
// export, its coordinates in float. The scene owns (and its destructor frees) everything
// allocated here.
std::unique_ptr<aiScene> make_scene(std::span<const std::array<double, 3>> vertices,
                                    std::span<const int> indices, int per_face) {
  auto scene = std::make_unique<aiScene>();
  scene->mRootNode = new aiNode();
  scene->mRootNode->mMeshes = new unsigned int[1]{0};
  scene->mRootNode->mNumMeshes = 1;
  scene->mMaterials = new aiMaterial* [1] { new aiMaterial() };
  scene->mNumMaterials = 1;
  auto* mesh = new aiMesh();
  scene->mMeshes = new aiMesh* [1] { mesh };
  scene->mNumMeshes = 1;
  mesh->mMaterialIndex = 0;
  mesh->mPrimitiveTypes = per_face == 3 ? aiPrimitiveType_TRIANGLE : aiPrimitiveType_LINE;
  mesh->mNumVertices = static_cast<unsigned int>(vertices.size());
  mesh->mVertices = new aiVector3D[vertices.size()];
  for (std::size_t v = 0; v < vertices.size(); ++v) {
    mesh->mVertices[v] =
        aiVector3D(static_cast<float>(vertices[v][0]), static_cast<float>(vertices[v][1]),
                   static_cast<float>(vertices[v][2]));
  }
  const std::size_t faces = indices.size() / static_cast<std::size_t>(per_face);
  mesh->mNumFaces = static_cast<unsigned int>(faces);
  mesh->mFaces = new aiFace[faces];
  for (std::size_t f = 0; f < faces; ++f) {
    aiFace& face = mesh->mFaces[f];
    face.mNumIndices = static_cast<unsigned int>(per_face);
    face.mIndices = new unsigned int[static_cast<std::size_t>(per_face)];
    for (int c = 0; c < per_face; ++c) {
      face.mIndices[c] = static_cast<unsigned int>(
          indices[f * static_cast<std::size_t>(per_face) + static_cast<std::size_t>(c)]);
    }
  }
  return scene;
}

void export_scene(const aiScene& scene, const char* format, const std::filesystem::path& path) {
  Assimp::Exporter exporter;
  const aiExportDataBlob* blob = exporter.ExportToBlob(&scene, format);
  if (blob == nullptr) {
    throw InputError(fmt::format("cannot write {}: {}", path.string(), exporter.GetErrorString()));
  }
  io::write_text_file_atomic(path,
                             std::string_view(static_cast<const char*>(blob->data), blob->size));
}

const char* mesh_format(const std::filesystem::path& path) {
  const std::string ext = lowercase_extension(path);
  if (ext == ".obj") return "objnomtl";
  if (ext == ".stl") return "stlb";
  if (ext == ".ply") return "plyb";
  throw InputError(
      fmt::format("{}: unknown mesh format '{}' (use .obj, .stl or .ply)", path.string(), ext));
}

}  // namespace

void write_mesh(const TriangleMesh& mesh, const std::filesystem::path& path) {
  const char* format = mesh_format(path);
  if (mesh.vertices.size() > std::numeric_limits<unsigned int>::max() / 2) {
    throw InputError(fmt::format("cannot write {}: the mesh is too large", path.string()));
  }
  const std::span<const int> indices(mesh.triangles.empty() ? nullptr : mesh.triangles[0].data(),
                                     mesh.triangles.size() * 3);
  const auto scene = make_scene(mesh.vertices, indices, 3);
  export_scene(*scene, format, path);
}

TriangleMesh read_triangle_mesh(const std::filesystem::path& path) {
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(path.string(), 0);
  if (scene == nullptr) {
    throw InputError(fmt::format("cannot read {}: {}", path.string(), importer.GetErrorString()));
  }
  TriangleMesh mesh;
  // The meshes as stored, each after the last (write_mesh() writes one, without transforms).
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh* in = scene->mMeshes[m];
    const auto base = static_cast<unsigned>(mesh.vertices.size());
    for (unsigned v = 0; v < in->mNumVertices; ++v) {
      const aiVector3D& p = in->mVertices[v];
      mesh.vertices.push_back({p.x, p.y, p.z});
    }
    for (unsigned f = 0; f < in->mNumFaces; ++f) {
      const aiFace& face = in->mFaces[f];
      if (face.mNumIndices != 3) continue;  // points and lines
      std::array<int, 3> t{};
      for (int c = 0; c < 3; ++c) {
        if (face.mIndices[c] >= in->mNumVertices) {
          throw InputError(fmt::format("cannot read {}: face {} refers to vertex {} of {}",
                                       path.string(), f, face.mIndices[c], in->mNumVertices));
        }
        t[static_cast<std::size_t>(c)] = static_cast<int>(base + face.mIndices[c]);
      }
      mesh.triangles.push_back(t);
    }
  }
  return mesh;
}

void write_contours(const Contours& contours, const Tree& tree, const std::filesystem::path& path) {
  const std::string ext = lowercase_extension(path);
  if (ext == ".obj") {
    std::vector<std::array<double, 3>> vertices;
    std::vector<int> segments;
    for (const auto& loop : contours.loops) {
      const int first = static_cast<int>(vertices.size());
      const int n = static_cast<int>(loop.size());
      for (const auto& p : loop) vertices.push_back({p[0], p[1], 0.0});
      for (int i = 0; i < n; ++i) {
        segments.push_back(first + i);
        segments.push_back(first + (i + 1) % n);
      }
    }
    const auto scene = make_scene(vertices, segments, 2);
    export_scene(*scene, "objnomtl", path);
    return;
  }
  if (ext != ".svg") {
    throw InputError(
        fmt::format("{}: unknown contour format '{}' (use .svg or .obj)", path.string(), ext));
  }
  // The domain as the view box, y up (SVG's y points down: flipped by the transform).
  const Domain d = tree.domain_or_default();
  const double w = d.max[0] - d.min[0], h = d.max[1] - d.min[1];
  const double px = 512.0 / std::max(w, h);
  std::string svg = fmt::format(
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{:.0f}\" height=\"{:.0f}\" "
      "viewBox=\"{} {} {} {}\">\n"
      "<g transform=\"scale(1,-1)\">\n"
      "<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"white\"/>\n"
      "<path fill=\"#4a7bd0\" fill-rule=\"evenodd\" stroke=\"black\" stroke-width=\"{}\" d=\"",
      w * px, h * px, d.min[0], -d.max[1], w, h, d.min[0], d.min[1], w, h, 1.5 / px);
  for (const auto& loop : contours.loops) {
    for (std::size_t i = 0; i < loop.size(); ++i) {
      svg += fmt::format("{}{:.6g} {:.6g}", i == 0 ? "M" : " L", loop[i][0], loop[i][1]);
    }
    svg += " Z ";
  }
  svg += "\"/>\n</g>\n</svg>\n";
  io::write_text_file_atomic(path, svg);
}

}  // namespace fuzzycsg
