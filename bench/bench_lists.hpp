#pragma once
// Small helpers the benches share: the median of timings and comma lists of sizes.

#include <algorithm>
#include <string>
#include <vector>

namespace fuzzycsg::bench {

// The median of v (the mean of the two middle elements of an even count); v must not be empty.
inline double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// "32,256" -> {32, 256}.
inline std::vector<int> parse_list(const std::string& s) {
  std::vector<int> out;
  std::size_t pos = 0;
  while (pos < s.size()) {
    const std::size_t comma = s.find(',', pos);
    out.push_back(std::stoi(s.substr(pos, comma - pos)));
    if (comma == std::string::npos) break;
    pos = comma + 1;
  }
  return out;
}

}  // namespace fuzzycsg::bench
