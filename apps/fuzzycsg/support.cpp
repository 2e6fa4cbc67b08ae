#include "support.hpp"

#include <fmt/format.h>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/io/points.hpp"

namespace fuzzycsg::app {

std::string& command_line() {
  static std::string line;
  return line;
}

void prepare_output_dir(const std::filesystem::path& dir) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::exists(dir, ec) && !fs::is_directory(dir, ec)) {
    throw InputError(
        fmt::format("{}: cannot create output directory (a file is there)", dir.string()));
  }
  fs::create_directories(dir, ec);
  if (ec) {
    throw InputError(
        fmt::format("{}: cannot create output directory ({})", dir.string(), ec.message()));
  }
  // Fail now, not after hours of work, when nothing can be written there.
  const fs::path probe = dir / ".fuzzycsg-write-test";
  io::write_text_file_atomic(probe, "");
  fs::remove(probe, ec);
}

CLI::Option* add_threads_option(CLI::App* cmd, int& threads, const std::string& help) {
  return cmd->add_option("--threads", threads, help.empty() ? "Threads (0: all cores)" : help)
      ->check(CLI::Range(0, kMaxThreads))
      ->capture_default_str();
}

}  // namespace fuzzycsg::app
