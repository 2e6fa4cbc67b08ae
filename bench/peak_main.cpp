// peak_bench: prints this machine's peak fp32 FMA and exp throughput on 1 and 2 threads (or the
// thread counts given), measured with the Highway target runtime dispatch picks for this CPU.
//
//   peak_bench [--threads 1,2] [--seconds 0.1] [--runs 5] [--json]
//
// Human-readable lines, or with --json one JSON line per thread count:
//   {"impl":"peak","threads":T,"target":"AVX3","lanes":16,"flops_per_s":...,"exps_per_s":...,
//    "flops_per_s_median":...,"exps_per_s_median":...,"runs":R}

#include <CLI/CLI.hpp>
#include <cstdio>
#include <thread>
#include <vector>

#include "bench/peak.hpp"

int main(int argc, char** argv) {
  std::vector<int> threads{1, 2};
  double seconds = 0.1;
  int runs = 5;
  bool json = false;
  CLI::App app{"Peak fp32 FMA and exp throughput of this machine (Highway, runtime dispatch)"};
  app.add_option("--threads", threads, "thread counts")->delimiter(',');
  app.add_option("--seconds", seconds, "seconds per timed run");
  app.add_option("--runs", runs, "timed runs per measurement (the best is the peak)");
  app.add_flag("--json", json, "print JSON lines");
  CLI11_PARSE(app, argc, argv);

  const auto simd = fuzzycsg::bench::simd_info();
  if (!json) {
    std::printf("Highway target: %s (%zu fp32 lanes); hardware threads: %u\n", simd.target.c_str(),
                simd.float_lanes, std::thread::hardware_concurrency());
  }
  for (int t : threads) {
    const auto r = fuzzycsg::bench::measure_peak(t, seconds, runs);
    if (json) {
      std::printf(
          "{\"impl\":\"peak\",\"threads\":%d,\"target\":\"%s\",\"lanes\":%zu,"
          "\"flops_per_s\":%.6g,\"exps_per_s\":%.6g,\"flops_per_s_median\":%.6g,"
          "\"exps_per_s_median\":%.6g,\"runs\":%d}\n",
          r.threads, simd.target.c_str(), simd.float_lanes, r.flops_per_s, r.exps_per_s,
          r.flops_per_s_median, r.exps_per_s_median, r.runs);
    } else {
      std::printf(
          "threads %d: FMA %.1f GFLOP/s (%.1f G FMA/s; median %.1f GFLOP/s), exp %.2f G exp/s "
          "(median %.2f), best of %d runs\n",
          t, r.flops_per_s * 1e-9, r.flops_per_s * 0.5e-9, r.flops_per_s_median * 1e-9,
          r.exps_per_s * 1e-9, r.exps_per_s_median * 1e-9, r.runs);
    }
    std::fflush(stdout);
  }
  return 0;
}
