#include "fuzzycsg/core/limits.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <string>
#include <thread>

#include "fuzzycsg/core/error.hpp"

namespace fuzzycsg {

namespace {
std::atomic<bool> g_cancel{false};
}  // namespace

void request_cancel() { g_cancel.store(true, std::memory_order_relaxed); }
void clear_cancel() { g_cancel.store(false, std::memory_order_relaxed); }
bool cancel_requested() { return g_cancel.load(std::memory_order_relaxed); }
void check_cancelled() {
  if (cancel_requested()) throw Cancelled();
}

void check_threads(int threads, const std::string& field) {
  if (threads < 0 || threads > kMaxThreads) {
    throw OptionError(field, "must be in 0.." + std::to_string(kMaxThreads) +
                                 " (0: all hardware threads; got " + std::to_string(threads) + ")");
  }
}

int thread_count(int threads, const std::string& field) {
  check_threads(threads, field);
  if (threads > 0) return threads;
  const int hardware = static_cast<int>(std::thread::hardware_concurrency());
  return std::clamp(hardware, 1, kMaxThreads);
}

SteadyClock::time_point deadline_after(SteadyClock::time_point start, double seconds) {
  if (!(seconds > 0)) return start;
  using Seconds = std::chrono::duration<double>;
  const double room =
      std::chrono::duration_cast<Seconds>(SteadyClock::time_point::max() - start).count();
  // Half the room: the conversion of a double near the limit back to ticks may round past it.
  if (!(seconds < 0.5 * room)) return SteadyClock::time_point::max();
  return start + std::chrono::duration_cast<SteadyClock::duration>(Seconds(seconds));
}

}  // namespace fuzzycsg
