// Reading whole files, and writing files atomically.
#include "fuzzycsg/io/files.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <random>
#include <string>

#include "fuzzycsg/core/error.hpp"
#include "io_detail.hpp"

namespace fuzzycsg::io {

namespace {

std::string temp_name_beside(const std::filesystem::path& path) {
  static std::atomic<unsigned> counter{0};
  std::random_device device;
  const std::string suffix = ".tmp." + std::to_string(::getpid()) + "." +
                             std::to_string(counter.fetch_add(1)) + "." +
                             std::to_string(device() % 1000000u);
  return path.string() + suffix;
}

}  // namespace

std::string read_file(const std::filesystem::path& path) { return detail::read_text_file(path); }

void write_text_file_atomic(const std::filesystem::path& path, std::string_view text) {
  const std::string temp = temp_name_beside(path);
  const auto fail = [&](const std::string& reason) -> void {
    ::unlink(temp.c_str());
    throw InputError("cannot write " + detail::display_name(path) + ": " + reason);
  };
  if (path.empty()) throw InputError("cannot write an unnamed file");
  const int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
  if (fd < 0) {
    // Nothing was created; report the reason without touching anything.
    throw InputError("cannot write " + detail::display_name(path) + ": " + std::strerror(errno));
  }
  std::size_t written = 0;
  while (written < text.size()) {
    const ssize_t n = ::write(fd, text.data() + written, text.size() - written);
    if (n < 0) {
      if (errno == EINTR) continue;
      const int error = errno;
      ::close(fd);
      fail(std::strerror(error));
    }
    written += static_cast<std::size_t>(n);
  }
  if (::fsync(fd) != 0) {
    const int error = errno;
    ::close(fd);
    fail(std::strerror(error));
  }
  if (::close(fd) != 0) fail(std::strerror(errno));
  if (::rename(temp.c_str(), path.c_str()) != 0) fail(std::strerror(errno));
}

}  // namespace fuzzycsg::io
