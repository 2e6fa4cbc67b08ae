#pragma once
// Declarations shared by the target sources (not part of the public interface).

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>

#include "fuzzycsg/core/limits.hpp"
#include "fuzzycsg/target/target.hpp"

namespace fuzzycsg::target_detail {

// The loaders behind load_target(); `name` is the file as messages name it.
std::unique_ptr<Target> load_mesh(const std::filesystem::path& path, const std::string& name,
                                  const TargetOptions& options);
std::unique_ptr<Target> load_image(const std::filesystem::path& path, const std::string& name,
                                   const TargetOptions& options);
std::unique_ptr<Target> load_tree(const std::filesystem::path& path, const std::string& name,
                                  const TargetOptions& options);

// Throws InputError naming the target for a padding outside [0, 1) or a negative thread count,
// and OptionError("threads") for more than kMaxThreads.
void check_options(const std::string& name, const TargetOptions& options);

// Throws InputError("NAME: problem").
[[noreturn]] void fail(const std::string& name, const std::string& problem);

// The whole file as bytes; InputError "NAME: cannot read (reason)" or "NAME: empty file".
std::string read_file_bytes(const std::filesystem::path& path, const std::string& name);

// The extension with its dot, in lower case: ".obj".
std::string lowercase_extension(const std::filesystem::path& path);

// The random numbers of every sampler come from these two functions, not from
// std::uniform_*_distribution, whose algorithms the standard leaves to each library: samples are
// the same for a seed whatever the standard library.
//
// Uniform in [0, 1), 53 random bits.
inline double uniform01(Rng& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }
// Uniform in [0, n), n > 0; unbiased (rejects the few draws above the last multiple of n).
std::size_t uniform_index(Rng& rng, std::size_t n);

}  // namespace fuzzycsg::target_detail
