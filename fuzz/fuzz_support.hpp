#pragma once
// What the fuzz targets share: reporting a bug (abort, so that libFuzzer saves the input), the
// check that an InputError message is one non-empty line, a per-process scratch folder for the
// loaders that read files only, and trial runs in a helper process that tell a crash inside a
// third-party library from one in our code.

#include <dlfcn.h>
#include <execinfo.h>
#include <fcntl.h>
#include <sanitizer/common_interface_defs.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <span>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/target/target.hpp"

namespace fuzzycsg::fuzz {

[[noreturn]] inline void bug(const char* target, const std::string& what,
                             std::string_view detail = {}) {
  std::fprintf(stderr, "%s: %s\n%.*s\n", target, what.c_str(), static_cast<int>(detail.size()),
               detail.data());
  std::abort();
}

// The expected answer to bad input: InputError with one non-empty line.
inline void check_message(const char* target, const InputError& e) {
  const std::string_view message = e.what();
  if (message.empty() || message.find('\n') != std::string_view::npos ||
      message.find('\r') != std::string_view::npos) {
    bug(target, "an InputError message is not one non-empty line", message);
  }
}

// What any loaded target owes: crisp occupancy (0 or 1) at `points`, and 16 boundary samples
// within `bound` of the origin along every axis, with finite normals.
inline void check_crisp_target(const char* target_name, const Target& target,
                               std::span<const float> points, float bound) {
  const auto dim = static_cast<std::size_t>(target.dim());
  std::vector<float> out(points.size() / dim, -1.0f);
  target.occupancy(points, out);
  for (const float o : out) {
    if (o != 0.0f && o != 1.0f) bug(target_name, "an occupancy that is not 0 or 1");
  }
  Rng rng(1);
  std::vector<float> boundary, normals;
  target.sample_boundary(16, rng, boundary, normals);
  if (boundary.size() != 16 * dim || normals.size() != 16 * dim) {
    bug(target_name, "boundary samples missing");
  }
  for (const float x : boundary) {
    if (!(std::abs(x) <= bound)) bug(target_name, "a boundary point outside the box");
  }
  for (const float x : normals) {
    if (!std::isfinite(x)) bug(target_name, "a boundary normal is not finite");
  }
}

// A folder of this process's own under the temporary directory, removed at exit.
class ScratchDir {
 public:
  explicit ScratchDir(const char* target) : target_(target) {
    std::error_code ec;
    dir_ = std::filesystem::temp_directory_path(ec) /
           (std::string(target) + "-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir_, ec);
    if (ec) bug(target, "cannot make the scratch folder " + dir_.string() + ": " + ec.message());
  }
  ~ScratchDir() {
    std::error_code ec;
    std::filesystem::remove_all(dir_, ec);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;

  // Writes `bytes` to a file `name` in the folder (replacing it) and returns its path.
  std::filesystem::path write(const std::string& name, std::string_view bytes) const {
    const std::filesystem::path path = dir_ / name;
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    out.close();
    if (!out) bug(target_, "cannot write " + path.string());
    return path;
  }

 private:
  const char* target_;
  std::filesystem::path dir_;
};

// Trial runs in a helper process, for code that calls a third-party library that is not
// instrumented and has bugs of its own (assimp). The helper, forked from the fuzzer, runs `fn`
// on each request it is sent; a crash, an abort, a sanitizer report or a run longer than
// `seconds` there is put down to the library when one of its frames (a shared object whose path
// contains `library`) is on the stack at that moment, and the helper is started again for the
// next request. Its output is discarded and libFuzzer never hears of it: the coverage that
// guides fuzzing comes from running the code again in the fuzzer's own process, which only an
// input that the library survived should do.
enum class Trial { kFinished, kDiedInLibrary, kDiedElsewhere };

namespace detail {

inline const char* trial_library = nullptr;
constexpr int kDiedInLibraryStatus = 97, kDiedElsewhereStatus = 98;

inline void trial_died() {
  void* frames[256];
  const int n = backtrace(frames, 256);
  for (int i = 0; i < n; ++i) {
    Dl_info info;
    if (dladdr(frames[i], &info) != 0 && info.dli_fname != nullptr &&
        std::strstr(info.dli_fname, trial_library) != nullptr) {
      _exit(kDiedInLibraryStatus);
    }
  }
  _exit(kDiedElsewhereStatus);
}

inline void trial_signal(int) { trial_died(); }

inline bool read_all(int fd, void* data, std::size_t size) {
  auto* p = static_cast<char*>(data);
  while (size > 0) {
    const ssize_t n = ::read(fd, p, size);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    p += n;
    size -= static_cast<std::size_t>(n);
  }
  return true;
}

inline bool write_all(int fd, const void* data, std::size_t size) {
  const auto* p = static_cast<const char*>(data);
  while (size > 0) {
    const ssize_t n = ::write(fd, p, size);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    p += n;
    size -= static_cast<std::size_t>(n);
  }
  return true;
}

}  // namespace detail

class TrialRunner {
 public:
  using Function = void (*)(const std::string& request);

  TrialRunner(const char* library, unsigned seconds, Function fn)
      : library_(library), seconds_(seconds), fn_(fn) {
    // A helper that died must not take the fuzzer with it when it is next written to.
    std::signal(SIGPIPE, SIG_IGN);
    // backtrace() loads the unwinder on first use: not in a signal handler.
    void* frame[1];
    backtrace(frame, 1);
  }
  ~TrialRunner() { stop(); }
  TrialRunner(const TrialRunner&) = delete;
  TrialRunner& operator=(const TrialRunner&) = delete;

  Trial run(const std::string& request) {
    if (pid_ <= 0 && !start()) return Trial::kDiedElsewhere;  // cannot tell: run it here
    const auto size = static_cast<std::uint32_t>(request.size());
    char answer = 0;
    if (detail::write_all(to_helper_, &size, sizeof size) &&
        detail::write_all(to_helper_, request.data(), request.size()) &&
        detail::read_all(from_helper_, &answer, 1)) {
      return Trial::kFinished;
    }
    // The helper died.
    int status = 0;
    while (::waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
    }
    close_pipes();
    pid_ = -1;
    if (WIFEXITED(status) && WEXITSTATUS(status) == detail::kDiedInLibraryStatus) {
      return Trial::kDiedInLibrary;
    }
    return Trial::kDiedElsewhere;
  }

 private:
  bool start() {
    int to[2], from[2];
    if (::pipe(to) != 0) return false;
    if (::pipe(from) != 0) {
      ::close(to[0]);
      ::close(to[1]);
      return false;
    }
    const pid_t pid = ::fork();
    if (pid < 0) {
      for (const int fd : {to[0], to[1], from[0], from[1]}) ::close(fd);
      return false;
    }
    if (pid == 0) serve(to[0], from[1], to[1], from[0]);
    ::close(to[0]);
    ::close(from[1]);
    pid_ = pid;
    to_helper_ = to[1];
    from_helper_ = from[0];
    return true;
  }

  [[noreturn]] void serve(int in, int out, int unused_in, int unused_out) {
    ::close(unused_in);
    ::close(unused_out);
    detail::trial_library = library_;
    __sanitizer_set_death_callback(detail::trial_died);
    struct sigaction action {};
    action.sa_handler = detail::trial_signal;
    action.sa_flags = SA_ONSTACK;
    sigemptyset(&action.sa_mask);
    for (const int signal : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT, SIGALRM}) {
      sigaction(signal, &action, nullptr);
    }
    const int null = ::open("/dev/null", O_WRONLY);
    if (null >= 0) {
      ::dup2(null, STDOUT_FILENO);
      ::dup2(null, STDERR_FILENO);
    }
    for (;;) {
      std::uint32_t size = 0;
      if (!detail::read_all(in, &size, sizeof size)) _exit(0);  // the fuzzer is done
      std::string request(size, '\0');
      if (!detail::read_all(in, request.data(), size)) _exit(0);
      ::alarm(seconds_);
      try {
        fn_(request);
      } catch (...) {
      }
      ::alarm(0);
      const char answer = 1;
      if (!detail::write_all(out, &answer, 1)) _exit(0);
    }
  }

  void close_pipes() {
    if (to_helper_ >= 0) ::close(to_helper_);
    if (from_helper_ >= 0) ::close(from_helper_);
    to_helper_ = from_helper_ = -1;
  }

  void stop() {
    if (pid_ <= 0) return;
    close_pipes();  // the helper reads the end of its input and exits
    int status = 0;
    while (::waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
    }
    pid_ = -1;
  }

  const char* library_;
  unsigned seconds_;
  Function fn_;
  pid_t pid_ = -1;
  int to_helper_ = -1, from_helper_ = -1;
};

// Counts the inputs a target skipped, and says how many at exit.
class SkipCounter {
 public:
  SkipCounter(const char* target, const char* why) : target_(target), why_(why) {}
  ~SkipCounter() {
    if (count_ > 0) std::fprintf(stderr, "%s: %zu inputs skipped: %s\n", target_, count_, why_);
  }
  SkipCounter(const SkipCounter&) = delete;
  SkipCounter& operator=(const SkipCounter&) = delete;
  void add() { ++count_; }

 private:
  const char* target_;
  const char* why_;
  std::size_t count_ = 0;
};

}  // namespace fuzzycsg::fuzz
