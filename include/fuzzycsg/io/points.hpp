#pragma once
// Point files: one point per line, coordinates separated by whitespace and/or commas; blank
// lines and lines starting with '#' are skipped. Errors name the file, the line and the column.

#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace fuzzycsg::io {

// Returns N x dim row-major floats.
std::vector<float> read_points_string(std::string_view text, int dim, std::string_view source);
std::vector<float> read_points_file(const std::filesystem::path& path, int dim);

}  // namespace fuzzycsg::io
