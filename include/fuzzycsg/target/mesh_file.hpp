#pragma once
// Triangle meshes from files (OBJ, STL, PLY, OFF) through assimp, as mesh targets read them:
// every mesh of the file moved by its node's transform (in double), triangulated, identical
// vertices joined, unused vertices dropped. Nothing is normalised.

#include <filesystem>

#include "fuzzycsg/core/triangle_mesh.hpp"

namespace fuzzycsg {

// Throws InputError naming the file for an unreadable file, a corrupt header, indices out of
// range, coordinates that are not finite, a mesh without triangles, or more vertices than a
// TriangleMesh's int indices can count (2^31 - 1).
TriangleMesh read_mesh_file(const std::filesystem::path& path);

}  // namespace fuzzycsg
