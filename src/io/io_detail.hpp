#pragma once
// Helpers shared by the io sources (not part of the public interface).

#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>

namespace fuzzycsg::io::detail {

// `s` as a one-line JSON string literal for messages: control characters escaped, bytes that
// are not UTF-8 written \xNN, cut after `max_chars` bytes (at a character boundary) with "..."
// appended.
std::string quote(std::string_view s, std::size_t max_chars = 60);

// `s` with control characters and bytes that are not UTF-8 escaped, for one-line messages.
std::string printable(std::string_view s);

// The whole file; throws InputError("cannot read PATH: reason").
std::string read_text_file(const std::filesystem::path& path);

// The name used for `path` in messages.
std::string display_name(const std::filesystem::path& path);

}  // namespace fuzzycsg::io::detail
