#pragma once
// Flush-to-zero and denormals-are-zero for the float kernel, for the lifetime of a scope on the
// calling thread. Saturated sigmoids (sharp primitives far from their surface) give
// occupancies and derivatives below 1.2e-38, and their products in the booleans; arithmetic on
// such subnormal floats takes microcode assists that made whole training steps several times
// slower. Treating them as zero changes no result by more than 1e-38.

#if defined(__x86_64__) || defined(_M_X64) || defined(__i386__)
#include <xmmintrin.h>
#define FUZZYCSG_HAVE_MXCSR 1
#endif

namespace fuzzycsg::eval_detail {

class FlushDenormals {
 public:
  explicit FlushDenormals(bool enable = true) : enabled_(enable) {
    if (!enabled_) return;
#if defined(FUZZYCSG_HAVE_MXCSR)
    saved_ = _mm_getcsr();
    _mm_setcsr(saved_ | kFlushToZero | kDenormalsAreZero);
#elif defined(__aarch64__)
    __asm__ __volatile__("mrs %0, fpcr" : "=r"(saved_));
    const unsigned long flushed = saved_ | (1UL << 24);  // FZ
    __asm__ __volatile__("msr fpcr, %0" : : "r"(flushed));
#endif
  }
  ~FlushDenormals() {
    if (!enabled_) return;
#if defined(FUZZYCSG_HAVE_MXCSR)
    _mm_setcsr(saved_);
#elif defined(__aarch64__)
    __asm__ __volatile__("msr fpcr, %0" : : "r"(saved_));
#endif
  }
  FlushDenormals(const FlushDenormals&) = delete;
  FlushDenormals& operator=(const FlushDenormals&) = delete;

 private:
  bool enabled_;
#if defined(FUZZYCSG_HAVE_MXCSR)
  static constexpr unsigned kFlushToZero = 0x8000;       // MXCSR.FTZ
  static constexpr unsigned kDenormalsAreZero = 0x0040;  // MXCSR.DAZ
  unsigned saved_ = 0;
#elif defined(__aarch64__)
  unsigned long saved_ = 0;
#endif
};

}  // namespace fuzzycsg::eval_detail
