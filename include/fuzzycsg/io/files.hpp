#pragma once
// Files as a whole: read into memory, and written atomically so that a reader never sees half a
// file and a failed run leaves an earlier file untouched. Errors are one line naming the file.

#include <filesystem>
#include <string>
#include <string_view>

namespace fuzzycsg::io {

// The whole file as bytes. Throws InputError "cannot read FILE: reason" if it cannot.
std::string read_file(const std::filesystem::path& path);

// Writes text atomically (a temporary file beside it, synced, then renamed over it). Throws
// InputError "cannot write FILE: reason" if it cannot; the temporary file is then removed.
void write_text_file_atomic(const std::filesystem::path& path, std::string_view text);

}  // namespace fuzzycsg::io
