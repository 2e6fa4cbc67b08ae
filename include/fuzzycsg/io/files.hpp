#pragma once
// Files as a whole: read into memory, and written atomically so that a reader never sees half a
// file and a failed run leaves an earlier file untouched. Errors are one line naming the file.

#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>

namespace fuzzycsg::io {

// The most bytes read of one file (a tree, a mesh, a picture): 1 GiB. A larger one (or an
// endless one, /dev/zero) is refused when the reading passes it.
inline constexpr std::size_t kMaxFileBytes = std::size_t{1} << 30;

// The whole file as bytes. Throws InputError "FILE: cannot read (reason)" if it cannot, and
// "FILE: larger than 1 GiB ..." past kMaxFileBytes.
std::string read_file(const std::filesystem::path& path);

// Writes text atomically (a temporary file beside it, synced, then renamed over it). Throws
// InputError "cannot write FILE: reason" if it cannot; the temporary file is then removed.
void write_text_file_atomic(const std::filesystem::path& path, std::string_view text);

}  // namespace fuzzycsg::io
