#pragma once
// Triangle meshes from files (OBJ, STL, PLY, OFF) through assimp, as mesh targets read them:
// every mesh of the file moved by its node's transform, triangulated, identical vertices
// joined, unused vertices dropped. Nothing is normalised.

#include <cstdint>
#include <filesystem>
#include <vector>

namespace fuzzycsg {

struct MeshData {
  std::vector<double> vertices;          // 3 per vertex
  std::vector<std::uint32_t> triangles;  // 3 per triangle
};

// Throws InputError naming the file for an unreadable file, a corrupt header, indices out of
// range, coordinates that are not finite, or a mesh without triangles.
MeshData read_mesh_file(const std::filesystem::path& path);

}  // namespace fuzzycsg
