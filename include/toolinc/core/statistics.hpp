// Order statistics of a set of values (taken by value: they are partially reordered), and the
// uncertainty of a measured rate.
#pragma once

#include <utility>
#include <vector>

namespace toolinc {

// The value at fraction q (clamped to [0, 1]) of the sorted values: element floor(q (n - 1)); 0 for none.
double quantile(std::vector<double> values, double q);

// The middle value, the upper of the two middle ones for an even count (element n / 2); NaN for none.
double median(std::vector<double> values);

// Wilson score interval of a success rate, `successes` of `trials`, at z standard deviations (1.96:
// 95 % confidence): unlike the normal approximation it stays inside [0, 1] and is honest near 0 and 1,
// where accuracy rates sit. {0, 1} for no trials.
std::pair<double, double> wilson_interval(int successes, int trials, double z = 1.96);

}  // namespace toolinc
