#pragma once
// Limits a caller puts on a run: the threads an option asks for, checked and counted (core
// starts no thread itself), and deadlines on the steady clock that hold for any number of
// seconds, infinity included.

#include <chrono>
#include <string>

namespace fuzzycsg {

// The most threads an option may ask for: oneTBB's own limit on the threads of one arena.
inline constexpr int kMaxThreads = 256;

// Throws OptionError(field, ...) unless 0 <= threads <= kMaxThreads (0: all hardware threads).
void check_threads(int threads, const std::string& field = "threads");

// The threads a run uses: `threads` when > 0, else the hardware's (at least 1, at most
// kMaxThreads). Checked as check_threads does.
int thread_count(int threads, const std::string& field = "threads");

using SteadyClock = std::chrono::steady_clock;

// `seconds` after `start`: the clock's last point (never reached) when that is past what the
// clock can hold (infinity, 1e300), and `start` itself for seconds <= 0 or NaN.
SteadyClock::time_point deadline_after(SteadyClock::time_point start, double seconds);

}  // namespace fuzzycsg
