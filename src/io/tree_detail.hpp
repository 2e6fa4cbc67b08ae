#pragma once
// What the tree reader and writer share (not part of the public interface): the format's name
// and version, the limits on hostile input, and the JSON document parser with its messages.

#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

namespace fuzzycsg::io::detail {

inline constexpr std::string_view kTreeFormat = "fuzzycsg-tree";
inline constexpr int kTreeVersion = 1;
// Hostile input must not exhaust the stack: JSON nesting and tree depth are bounded. A node at
// depth d sits at JSON level 2 + 2d and its deepest numbers at level 5 + 2d, so every tree of
// depth <= kMaxTreeDepth fits within kMaxNesting.
inline constexpr std::size_t kMaxNesting = 512;
inline constexpr int kMaxTreeDepth = 250;

// "source: path: " (either part left out when empty), the start of every message.
std::string prefix(std::string_view source, const std::string& path);

// The JSON document of `text`: duplicate keys, nesting deeper than kMaxNesting, numbers too
// large for a double, blank input and syntax errors throw InputError with one line naming
// `source`, the path or line and column, and the problem.
nlohmann::json parse_document(std::string_view text, std::string_view source);

}  // namespace fuzzycsg::io::detail
