#pragma once
// The median of a run of timings, as every timed table of the project reports (ldlpgs bench,
// step, sweep, peers): the upper middle value of an even count; 0 for no timings.
#include <algorithm>
#include <vector>

namespace ldlpgs {

inline double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

}  // namespace ldlpgs
