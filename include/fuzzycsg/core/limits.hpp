#pragma once
// Limits a caller puts on a run: the threads an option asks for, checked and counted (core
// starts no thread itself), and deadlines on the steady clock that hold for any number of
// seconds, infinity included.

#include <chrono>
#include <string>

#include "fuzzycsg/core/error.hpp"

namespace fuzzycsg {

// The most threads an option may ask for: oneTBB's own limit on the threads of one arena.
inline constexpr int kMaxThreads = 256;

// Throws OptionError(field, ...) unless 0 <= threads <= kMaxThreads (0: all hardware threads).
void check_threads(int threads, const std::string& field = "threads");

// The threads a run uses: `threads` when > 0, else the hardware's (at least 1, at most
// kMaxThreads). Checked as check_threads does.
int thread_count(int threads, const std::string& field = "threads");

// Cancellation: a program asks every engine running in the process to stop (the Python module
// does on Ctrl-C, whose signal the interpreter only sees between Python's own steps). The
// engines call check_cancelled() between their steps: the evaluator at each forward and
// backward pass, the searches of convert and trace and the refinements at each step. It throws
// Cancelled, which the program that asked catches; nothing an engine writes is half done, since
// results are handed back only when it returns.
class Cancelled : public Error {
 public:
  Cancelled() : Error("cancelled") {}
};
void request_cancel();
void clear_cancel();
bool cancel_requested();
// Throws Cancelled when a cancellation was requested (and not cleared since).
void check_cancelled();

using SteadyClock = std::chrono::steady_clock;

// `seconds` after `start`: the clock's last point (never reached) when that is past what the
// clock can hold (infinity, 1e300), and `start` itself for seconds <= 0 or NaN.
SteadyClock::time_point deadline_after(SteadyClock::time_point start, double seconds);

}  // namespace fuzzycsg
