#pragma once
/// @file Statistics.h
/// Summary statistics of a sample (timings, counts, errors).

#include <cstddef>
#include <vector>

namespace lidarseg {

/// Summary of a sample of values. All fields are 0 for an empty sample.
struct Summary {
  std::size_t count = 0;
  double mean = 0.0;
  /// Sample standard deviation (n - 1 in the denominator); 0 for fewer than 2 values.
  double stddev = 0.0;
  double min = 0.0;
  double median = 0.0;
  /// 99th percentile (linear interpolation between order statistics).
  double p99 = 0.0;
  double max = 0.0;
};

/// Summarises `values` (copied and sorted internally). O(n log n).
Summary summarize(std::vector<double> values);

/// The q-quantile (0 <= q <= 1) of an already sorted, non-empty sample, with linear
/// interpolation between order statistics (between an infinite one and another: the nearer
/// of the two, never NaN).
double quantileSorted(const std::vector<double>& sorted, double q);

}  // namespace lidarseg
