// An output folder replaced as a set (output_dir.hpp).
#include "fuzzycsg/io/output_dir.hpp"

#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstring>
#include <string>
#include <system_error>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/io/files.hpp"

namespace fuzzycsg::io {

namespace fs = std::filesystem;

namespace {

// ".NAME.fuzzycsg-PID-K": a temporary folder beside the output folder NAME.
constexpr const char* kTag = ".fuzzycsg-";

fs::path temp_beside(const fs::path& dir) {
  static std::atomic<unsigned> counter{0};
  return dir.parent_path() / ("." + dir.filename().string() + kTag + std::to_string(::getpid()) +
                              "-" + std::to_string(counter.fetch_add(1)));
}

// The folder as an absolute path (so that "out" has a parent to put its temporary beside),
// with its trailing separators dropped ("out/" is "out").
fs::path normal(const fs::path& dir) {
  fs::path d = fs::absolute(dir).lexically_normal();
  if (!d.has_filename()) d = d.parent_path();
  return d;
}

// Temporary folders of runs that are no longer alive, beside `dir`.
void remove_stale(const fs::path& dir) {
  const std::string prefix = "." + dir.filename().string() + kTag;
  std::error_code ec;
  for (fs::directory_iterator it(dir.parent_path(), ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (!name.starts_with(prefix)) continue;
    const std::string rest = name.substr(prefix.size());
    const pid_t pid = static_cast<pid_t>(std::atol(rest.c_str()));
    if (pid <= 0 || (::kill(pid, 0) != 0 && errno == ESRCH)) {
      std::error_code ignored;
      fs::remove_all(it->path(), ignored);
    }
  }
}

bool is_temporary(const std::string& name) {
  return name.find(".tmp.") != std::string::npos;  // write_text_file_atomic's, of killed runs
}

}  // namespace

OutputDir::OutputDir(fs::path dir, std::vector<std::string> names)
    : dir_(normal(dir)), names_(std::move(names)) {}

void OutputDir::check() const {
  const std::string shown = dir_.string();
  std::error_code ec;
  const fs::file_status st = fs::symlink_status(dir_, ec);
  if (fs::exists(st) && !fs::is_directory(st)) {
    throw InputError(shown + ": cannot be the output folder (a file is there)");
  }
  if (fs::is_directory(st)) {
    for (fs::directory_iterator it(dir_, ec), end; !ec && it != end; it.increment(ec)) {
      const std::string name = it->path().filename().string();
      if (is_temporary(name)) continue;
      if (std::find(names_.begin(), names_.end(), name) == names_.end()) {
        throw InputError(shown + ": holds " + name +
                         ", which this verb does not write: name a new or empty output folder "
                         "(the folder is replaced as a whole)");
      }
    }
    if (ec) throw InputError(shown + ": cannot read the output folder (" + ec.message() + ")");
  }
  // Nothing is created before the work: the nearest folder above it that exists must let us
  // create what is missing below it.
  fs::path above = dir_.parent_path();
  while (!above.empty() && !fs::exists(above, ec)) above = above.parent_path();
  if (above.empty()) above = fs::current_path();
  if (!fs::is_directory(above, ec) || ::access(above.c_str(), W_OK | X_OK) != 0) {
    throw InputError(shown + ": cannot create the output folder (" + above.string() +
                     (fs::is_directory(above, ec) ? " is not writable)" : " is not a folder)"));
  }
}

void OutputDir::add(const std::string& name, std::string bytes) {
  if (std::find(names_.begin(), names_.end(), name) == names_.end()) {
    throw Error("OutputDir: " + name + " is not one of the set's files");
  }
  files_.emplace_back(name, std::move(bytes));
}

void OutputDir::commit() {
  check();
  remove_stale(dir_);
  const fs::path temp = temp_beside(dir_);
  const auto fail = [&](const std::string& reason) {
    std::error_code ignored;
    fs::remove_all(temp, ignored);
    throw InputError("cannot write " + dir_.string() + ": " + reason);
  };
  std::error_code ec;
  fs::create_directories(dir_.parent_path(), ec);
  if (ec) fail(ec.message());
  if (!fs::create_directory(temp, ec)) fail(ec ? ec.message() : "exists");
  try {
    for (const auto& [name, bytes] : files_) write_text_file_atomic(temp / name, bytes);
  } catch (const InputError& e) {
    fail(e.what());
  }
  // The folder's entry itself synced, so that the files are in it after a crash.
  if (const int fd = ::open(temp.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC); fd >= 0) {
    ::fsync(fd);
    ::close(fd);
  }
  if (fs::is_directory(dir_)) {
    if (::renameat2(AT_FDCWD, temp.c_str(), AT_FDCWD, dir_.c_str(), RENAME_EXCHANGE) != 0) {
      fail(std::strerror(errno));
    }
    fs::remove_all(temp, ec);  // the old set, now at the temporary name
  } else if (::rename(temp.c_str(), dir_.c_str()) != 0) {
    fail(std::strerror(errno));
  }
  files_.clear();
}

}  // namespace fuzzycsg::io
