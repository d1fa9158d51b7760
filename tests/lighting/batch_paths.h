// What the batch-path tests of the lighting methods share: random grids and lights, and the
// error measure. Each method's test (tests/lighting/<method>/test_*_batch_paths.cpp) holds the
// CPU's batch paths to the per-cell kernel they stand in for, on the CPU alone (they run under
// VOXLUX_SKIP_GL=1 and in a VOXLUX_GL=OFF build): the GL backend runs the per-cell kernel, so this
// is what ties the backends' arithmetic together where no GL is.
#pragma once
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "kernel/kernel_types.h"

namespace voxlux::test {

inline std::vector<float> randomValues(size_t n, float peak, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<float> v(n);
    for (auto& x : v) x = peak * u(rng) * u(rng);   // many thin cells, a few dense ones
    return v;
}

inline kernel::VxLight directionalLight(glm::vec3 travel) {
    kernel::VxLight l{};
    l.type = VX_LIGHT_DIRECTIONAL;
    l.direction = glm::normalize(travel);
    l.cos_outer = l.cos_inner = 1.0f;
    l.color = glm::vec3(2.0f, 1.5f, 1.0f);
    return l;
}

inline kernel::VxLight pointLight(glm::vec3 position) {
    kernel::VxLight l{};
    l.type = VX_LIGHT_POINT;
    l.position = position;
    l.direction = glm::vec3(0.0f, -1.0f, 0.0f);
    l.cos_outer = l.cos_inner = 1.0f;
    l.color = glm::vec3(40.0f);
    return l;
}

// Largest |a - b| over the peak of |b|.
inline double relativeError(const std::vector<float>& a, const std::vector<float>& b) {
    double worst = 0.0, peak = 0.0;
    for (size_t i = 0; i < a.size(); ++i) {
        worst = std::max(worst, std::abs(double(a[i]) - double(b[i])));
        peak = std::max(peak, std::abs(double(b[i])));
    }
    return peak > 0.0 ? worst / peak : worst;
}

}  // namespace voxlux::test
