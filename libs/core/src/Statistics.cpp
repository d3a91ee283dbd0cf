#include "lidarseg/core/Statistics.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace lidarseg {

double quantileSorted(const std::vector<double>& sorted, double q) {
  const double pos = std::clamp(q, 0.0, 1.0) * static_cast<double>(sorted.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(pos));
  const std::size_t hi = std::min(lo + 1, sorted.size() - 1);
  const double frac = pos - static_cast<double>(lo);
  // On a sample itself or between equal ones: no interpolation (inf + 0 * (inf - inf) is NaN).
  if (frac == 0.0 || sorted[hi] == sorted[lo]) return sorted[lo];
  // Beside an infinite sample the nearer one (-inf + f * (x + inf) is NaN).
  if (!std::isfinite(sorted[lo]) || !std::isfinite(sorted[hi])) return frac < 0.5 ? sorted[lo] : sorted[hi];
  return sorted[lo] + frac * (sorted[hi] - sorted[lo]);
}

Summary summarize(std::vector<double> values) {
  Summary s;
  s.count = values.size();
  if (values.empty()) return s;
  std::sort(values.begin(), values.end());
  const double n = static_cast<double>(values.size());
  s.mean = std::accumulate(values.begin(), values.end(), 0.0) / n;
  if (values.size() > 1) {
    double sq = 0.0;
    for (double v : values) sq += (v - s.mean) * (v - s.mean);
    s.stddev = std::sqrt(sq / (n - 1.0));
  }
  s.min = values.front();
  s.max = values.back();
  s.median = quantileSorted(values, 0.5);
  s.p99 = quantileSorted(values, 0.99);
  return s;
}

}  // namespace lidarseg
