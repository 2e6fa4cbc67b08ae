#include "support.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <functional>
#include <map>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/io/files.hpp"

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

std::string flag_for(const std::string& field) {
  static const std::map<std::string, std::string, std::less<>> kNamed = {
      {"families", "--family"},
      {"iterations", "--iters"},
      {"random_view_every", "--random-views"},
      {"local.max_iterations", "--iterations"},
      {"local.k", "--k"},
      {"metrics.points", "--metric-points"},
      {"sampling", "--surface, --near"},
      {"sampling.scheme", "--sampler"},
  };
  if (const auto it = kNamed.find(field); it != kNamed.end()) return it->second;
  std::string flag = "--" + field.substr(field.rfind('.') + 1);
  for (char& c : flag) {
    if (c == '_') c = '-';
  }
  return flag;
}

void refuse_control_characters(const std::string& path, const std::string& what) {
  const auto control = [](char c) { return static_cast<unsigned char>(c) < 0x20; };
  if (std::none_of(path.begin(), path.end(), control)) return;
  std::string shown;
  for (const char c : path) shown += control(c) ? fmt::format("\\x{:02x}", c) : std::string(1, c);
  throw InputError(
      fmt::format("{}: {}: a path with a control character (a newline?) is refused", shown, what));
}

const CLI::Validator& unsigned_number() {
  static const CLI::Validator v(
      [](std::string& text) {
        const auto first = text.find_first_not_of(" \t");
        return first != std::string::npos && text[first] == '-'
                   ? std::string("must be a whole number >= 0 (got " + text + ")")
                   : std::string();
      },
      "UINT");
  return v;
}

CLI::Option* add_threads_option(CLI::App* cmd, int& threads, const std::string& help) {
  return cmd->add_option("--threads", threads, help.empty() ? "Threads (0: all cores)" : help)
      ->check(CLI::Range(0, kMaxThreads))
      ->capture_default_str();
}

bool has_extension(const std::string& path, std::initializer_list<const char*> exts) {
  std::string e = std::filesystem::path(path).extension().string();
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return std::tolower(c); });
  return std::any_of(exts.begin(), exts.end(), [&](const char* x) { return e == x; });
}

}  // namespace fuzzycsg::app
