// Engine calls that Ctrl-C interrupts (common.hpp, interruptible).

#include <chrono>
#include <condition_variable>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>

#include "common.hpp"
#include "fuzzycsg/core/limits.hpp"

namespace fuzzycsg::python {

void interruptible(const std::function<void()>& work) {
  std::exception_ptr error;
  std::mutex mutex;
  std::condition_variable finished;
  bool done = false;
  std::thread worker([&] {
    try {
      work();
    } catch (...) {
      error = std::current_exception();
    }
    const std::lock_guard lock(mutex);
    done = true;
    finished.notify_one();
  });
  for (;;) {
    bool over = false;
    {
      const py::gil_scoped_release release;
      std::unique_lock lock(mutex);
      over = finished.wait_for(lock, std::chrono::milliseconds(50), [&] { return done; });
    }
    if (over) break;
    if (PyErr_CheckSignals() != 0) {  // KeyboardInterrupt (or another handler's exception) set
      request_cancel();
      {
        const py::gil_scoped_release release;
        worker.join();
      }
      clear_cancel();
      throw py::error_already_set();
    }
  }
  worker.join();
  if (error) std::rethrow_exception(error);
}

}  // namespace fuzzycsg::python
