// Order statistics of a set of values (taken by value: they are partially reordered).
#pragma once

#include <vector>

namespace toolinc {

// The value at fraction q (clamped to [0, 1]) of the sorted values: element floor(q (n - 1)); 0 for none.
double quantile(std::vector<double> values, double q);

// The middle value, the upper of the two middle ones for an even count (element n / 2); NaN for none.
double median(std::vector<double> values);

}  // namespace toolinc
