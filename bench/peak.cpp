// Peak fp32 FMA and exp throughput (see peak.hpp). The kernels are compiled once per Highway
// target (foreach_target.h) and called through HWY_DYNAMIC_DISPATCH.

#include "bench/peak.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <thread>
#include <vector>

#include "bench/bench_lists.hpp"

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "bench/peak.cpp"
// clang-format off
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/highway.h"
#include "hwy/contrib/math/math-inl.h"
// clang-format on

HWY_BEFORE_NAMESPACE();
namespace fuzzycsg::bench {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// iters * 16 vector FMAs. Sixteen independent chains cover FMA latency (4-5 cycles) times the
// number of FMA pipes (2) with room to spare, and still fit in the register file together with
// the two constants. acc -> acc * m + a converges to a / (1 - m) = 1: no overflow, no denormals.
float FmaChains(std::uint64_t iters) {
  const hn::ScalableTag<float> d;
  const auto m = hn::Set(d, 0.999f);
  const auto a = hn::Set(d, 0.001f);
  auto a0 = hn::Set(d, 0.50f), a1 = hn::Set(d, 0.51f), a2 = hn::Set(d, 0.52f);
  auto a3 = hn::Set(d, 0.53f), a4 = hn::Set(d, 0.54f), a5 = hn::Set(d, 0.55f);
  auto a6 = hn::Set(d, 0.56f), a7 = hn::Set(d, 0.57f), a8 = hn::Set(d, 0.58f);
  auto a9 = hn::Set(d, 0.59f), a10 = hn::Set(d, 0.60f), a11 = hn::Set(d, 0.61f);
  auto a12 = hn::Set(d, 0.62f), a13 = hn::Set(d, 0.63f), a14 = hn::Set(d, 0.64f);
  auto a15 = hn::Set(d, 0.65f);
  for (std::uint64_t i = 0; i < iters; ++i) {
    a0 = hn::MulAdd(a0, m, a);
    a1 = hn::MulAdd(a1, m, a);
    a2 = hn::MulAdd(a2, m, a);
    a3 = hn::MulAdd(a3, m, a);
    a4 = hn::MulAdd(a4, m, a);
    a5 = hn::MulAdd(a5, m, a);
    a6 = hn::MulAdd(a6, m, a);
    a7 = hn::MulAdd(a7, m, a);
    a8 = hn::MulAdd(a8, m, a);
    a9 = hn::MulAdd(a9, m, a);
    a10 = hn::MulAdd(a10, m, a);
    a11 = hn::MulAdd(a11, m, a);
    a12 = hn::MulAdd(a12, m, a);
    a13 = hn::MulAdd(a13, m, a);
    a14 = hn::MulAdd(a14, m, a);
    a15 = hn::MulAdd(a15, m, a);
  }
  const auto s0 =
      hn::Add(hn::Add(hn::Add(a0, a1), hn::Add(a2, a3)), hn::Add(hn::Add(a4, a5), hn::Add(a6, a7)));
  const auto s1 = hn::Add(hn::Add(hn::Add(a8, a9), hn::Add(a10, a11)),
                          hn::Add(hn::Add(a12, a13), hn::Add(a14, a15)));
  return hn::GetLane(hn::SumOfLanes(d, hn::Add(s0, s1)));
}

// reps passes of out[i] = exp(in[i]) over n floats (n a multiple of the vector length). The
// compiler barrier between passes keeps every pass from being hoisted or merged.
float ExpStream(std::uint64_t reps, const float* HWY_RESTRICT in, float* HWY_RESTRICT out,
                std::size_t n) {
  const hn::ScalableTag<float> d;
  const std::size_t lanes = hn::Lanes(d);
  for (std::uint64_t r = 0; r < reps; ++r) {
    for (std::size_t i = 0; i < n; i += lanes) {
      hn::StoreU(hn::Exp(d, hn::LoadU(d, in + i)), d, out + i);
    }
    __asm__ __volatile__("" : : "r"(out) : "memory");
  }
  auto sum = hn::Zero(d);
  for (std::size_t i = 0; i < n; i += lanes) sum = hn::Add(sum, hn::LoadU(d, out + i));
  return hn::GetLane(hn::SumOfLanes(d, sum));
}

std::int64_t Target() { return HWY_TARGET; }
std::size_t FloatLanes() { return hn::Lanes(hn::ScalableTag<float>()); }

}  // namespace HWY_NAMESPACE
}  // namespace fuzzycsg::bench
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace fuzzycsg::bench {

HWY_EXPORT(FmaChains);
HWY_EXPORT(ExpStream);
HWY_EXPORT(Target);
HWY_EXPORT(FloatLanes);

namespace {

using Clock = std::chrono::steady_clock;

// Results are summed here so that no kernel call is dead code.
std::atomic<float> g_sink{0.0f};

constexpr std::size_t kExpArray = 2048;  // 8 KiB in, 8 KiB out: stays in L1
constexpr std::uint64_t kFmaPerIter = 16;

// Runs work(thread_index) on `threads` threads released together; returns the seconds from the
// release to the end of the slowest thread.
template <class Work>
double run_on_threads(int threads, const Work& work) {
  std::atomic<int> ready{0};
  std::atomic<bool> go{false};
  std::vector<Clock::time_point> ends(static_cast<std::size_t>(threads));
  std::vector<std::thread> pool;
  pool.reserve(static_cast<std::size_t>(threads));
  for (int t = 0; t < threads; ++t) {
    pool.emplace_back([&, t] {
      ready.fetch_add(1, std::memory_order_acq_rel);
      while (!go.load(std::memory_order_acquire)) std::this_thread::yield();
      work(t);
      ends[static_cast<std::size_t>(t)] = Clock::now();
    });
  }
  while (ready.load(std::memory_order_acquire) < threads) std::this_thread::yield();
  const auto start = Clock::now();
  go.store(true, std::memory_order_release);
  for (auto& th : pool) th.join();
  const auto end = *std::max_element(ends.begin(), ends.end());
  return std::chrono::duration<double>(end - start).count();
}

struct Rates {
  double best = 0, median = 0;
};

// Measures `units` per second of kernel(count, thread) on `threads` threads, where one call
// performs count * units_per_count units.
template <class Kernel>
Rates measure(int threads, double seconds_per_run, int runs, double units_per_count,
              const Kernel& kernel) {
  // Calibrate on one thread: grow the count until a call takes at least 10 ms.
  std::uint64_t count = 1024;
  double t = 0;
  for (;;) {
    const auto t0 = Clock::now();
    kernel(count, 0);
    t = std::chrono::duration<double>(Clock::now() - t0).count();
    if (t >= 0.01) break;
    count *= 4;
  }
  count = std::max<std::uint64_t>(1, static_cast<std::uint64_t>(count * (seconds_per_run / t)));
  kernel(count / 8 + 1, 0);  // warm-up
  std::vector<double> rates;
  for (int r = 0; r < runs; ++r) {
    const double wall = run_on_threads(threads, [&](int th) { kernel(count, th); });
    rates.push_back(static_cast<double>(threads) * static_cast<double>(count) * units_per_count /
                    wall);
  }
  return {*std::max_element(rates.begin(), rates.end()), median(rates)};
}

}  // namespace

SimdInfo simd_info() {
  SimdInfo info;
  info.target = hwy::TargetName(HWY_DYNAMIC_DISPATCH(Target)());
  info.float_lanes = HWY_DYNAMIC_DISPATCH(FloatLanes)();
  return info;
}

PeakResult measure_peak(int threads, double seconds_per_run, int runs) {
  threads = std::max(1, threads);
  runs = std::max(1, runs);
  const double lanes = static_cast<double>(HWY_DYNAMIC_DISPATCH(FloatLanes)());

  const Rates fma = measure(threads, seconds_per_run, runs, 2.0 * kFmaPerIter * lanes,
                            [](std::uint64_t iters, int) {
                              const float r = HWY_DYNAMIC_DISPATCH(FmaChains)(iters);
                              g_sink.fetch_add(r, std::memory_order_relaxed);
                            });

  // One input/output array pair per thread, inputs spread over [-8, 8].
  std::vector<std::vector<float>> in(static_cast<std::size_t>(threads)),
      out(static_cast<std::size_t>(threads));
  for (int t = 0; t < threads; ++t) {
    auto& v = in[static_cast<std::size_t>(t)];
    v.resize(kExpArray);
    for (std::size_t i = 0; i < kExpArray; ++i) {
      v[i] = -8.0f + 16.0f *
                         static_cast<float>((i * 7919 + static_cast<std::size_t>(t)) % kExpArray) /
                         static_cast<float>(kExpArray);
    }
    out[static_cast<std::size_t>(t)].assign(kExpArray, 0.0f);
  }
  const Rates exps = measure(threads, seconds_per_run, runs, static_cast<double>(kExpArray),
                             [&](std::uint64_t reps, int t) {
                               const auto ti = static_cast<std::size_t>(t);
                               const float r = HWY_DYNAMIC_DISPATCH(ExpStream)(
                                   reps, in[ti].data(), out[ti].data(), kExpArray);
                               g_sink.fetch_add(r, std::memory_order_relaxed);
                             });

  PeakResult result;
  result.threads = threads;
  result.runs = runs;
  result.flops_per_s = fma.best;
  result.flops_per_s_median = fma.median;
  result.exps_per_s = exps.best;
  result.exps_per_s_median = exps.median;
  return result;
}

}  // namespace fuzzycsg::bench
#endif  // HWY_ONCE
