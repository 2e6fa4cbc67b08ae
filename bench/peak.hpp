#pragma once
// Peak fp32 arithmetic throughput of this machine, measured with Highway on the SIMD target
// that runtime dispatch picks for this CPU (the same mechanism the evaluator uses):
//   - FMA: 16 independent accumulator chains acc = acc * m + a per thread, so the FMA pipes are
//     kept busy (throughput, not latency); an FMA counts as 2 flops.
//   - exp: hwy::Exp over an L1-resident array (independent elements, results stored).
// Each measurement runs the same amount of work on every thread, all threads released together;
// throughput = total work / wall time until the last thread finishes.

#include <cstddef>
#include <string>

namespace fuzzycsg::bench {

struct SimdInfo {
  std::string target;  // Highway target name, e.g. "AVX3"
  std::size_t float_lanes = 0;
};

// The target HWY_DYNAMIC_DISPATCH selects on this CPU.
SimdInfo simd_info();

struct PeakResult {
  int threads = 0;
  double flops_per_s = 0;  // best run: fp32 FLOP/s, an FMA counted as 2 flops
  double exps_per_s = 0;   // best run: fp32 exp evaluations per second
  double flops_per_s_median = 0;
  double exps_per_s_median = 0;
  int runs = 0;
};

// `runs` timed runs of about `seconds_per_run` each, per kind, after a calibration run.
PeakResult measure_peak(int threads, double seconds_per_run = 0.1, int runs = 5);

}  // namespace fuzzycsg::bench
