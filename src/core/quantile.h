// The q-quantile of a sample by selection (std::nth_element, linear time): the value at rank
// floor(q * n), clamped to the last, with no interpolation; 0 for an empty sample.
#pragma once
#include <algorithm>
#include <cstddef>
#include <vector>

namespace voxlux {

inline double quantile(std::vector<double> values, double q) {
    if (values.empty()) return 0.0;
    const size_t k = std::min(values.size() - 1, size_t(q * double(values.size())));
    std::nth_element(values.begin(), values.begin() + std::ptrdiff_t(k), values.end());
    return values[k];
}

}  // namespace voxlux
