#pragma once
// Reading and writing tree files (format "fuzzycsg-tree", version 1; docs/tree-format.md).
//
// read_* validate everything and throw InputError with one line naming the source, the node
// path and the field: "tree.json: root.children[1].radius: must be > 0 (got -0.2)".
// write_* produce a file that reads back to an identical Tree (same nodes, same parameter
// table, bit-identical numbers).

#include <filesystem>
#include <string>
#include <string_view>

#include "fuzzycsg/core/tree.hpp"

namespace fuzzycsg::io {

Tree read_tree_string(std::string_view text, std::string_view source = "<string>");
Tree read_tree_file(const std::filesystem::path& path);

std::string write_tree_string(const Tree& tree);
// Writes atomically: to a temporary file beside `path`, then renames it over `path`.
void write_tree_file(const Tree& tree, const std::filesystem::path& path);

}  // namespace fuzzycsg::io
