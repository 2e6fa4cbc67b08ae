#pragma once
// Tree files as text, for tests that write them by hand.

#include <string>

namespace fuzzycsg::test {

// A whole 3D (2D) tree file around the JSON of its root node.
inline std::string tree3(const std::string& root) {
  return R"({"format": "fuzzycsg-tree", "version": 1, "dim": 3, "root": )" + root + "}";
}
inline std::string tree2(const std::string& root) {
  return R"({"format": "fuzzycsg-tree", "version": 1, "dim": 2, "root": )" + root + "}";
}

}  // namespace fuzzycsg::test
