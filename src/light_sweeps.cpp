#include "light_sweeps.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>

namespace voxlux {

std::vector<Sweep> sweepsFor(glm::vec3 flow, bool blend) {
    const float len = glm::length(flow);
    const glm::vec3 f = len > 0.0f ? flow / len : glm::vec3(0.0f, 0.0f, 1.0f);
    std::array<float, 3> theta;
    for (int a = 0; a < 3; ++a) theta[size_t(a)] = std::acos(std::min(std::abs(f[a]), 1.0f));
    // Ties (a light on a face diagonal) go to z, then y: their slices are rows of x, contiguous in
    // memory, where an x sweep has to work on a transposed copy.
    std::array<int, 3> order{2, 1, 0};
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return theta[size_t(a)] < theta[size_t(b)]; });
    auto sweep = [&](int axis, float weight) { return Sweep{axis, f[axis] < 0.0f ? -1 : 1, weight}; };
    if (!blend) return {sweep(order[0], 1.0f)};
    const float t0 = theta[size_t(order[0])], t1 = theta[size_t(order[1])], t2 = theta[size_t(order[2])];
    float w0 = t2 - t0, w1 = t2 - t1;
    // On a body diagonal all three angles are equal: any split of two axes is as good as another.
    if (w0 + w1 <= 1e-7f) w0 = w1 = 0.5f;
    const float sum = w0 + w1;
    std::vector<Sweep> out{sweep(order[0], w0 / sum)};
    if (w1 > 0.0f) out.push_back(sweep(order[1], w1 / sum));
    return out;
}

std::vector<glm::vec4> blurTaps(const Indirect& in) {
    const float tan_half = std::tan(glm::radians(0.5f * in.angle));
    auto weight = [&](float r) {
        const float cos_a = 1.0f / std::sqrt(1.0f + r * r * tan_half * tan_half);
        if (in.phase == BlurPhase::Phong) return std::pow(cos_a, in.exponent);
        const float g = in.g, denom = 1.0f + g * g - 2.0f * g * cos_a;
        return (1.0f - g * g) / (denom * std::sqrt(denom));
    };
    std::vector<glm::vec4> taps;
    if (in.samples % 2 == 1) taps.push_back({0.0f, 0.0f, weight(0.0f), 0.0f});
    // Opposite pairs on a Vogel spiral: even coverage of the disc, and a weighted centre exactly at
    // the light's own direction, so the blur never drifts the light sideways.
    const int pairs = in.samples / 2;
    const float golden = 2.39996323f;  // radians
    for (int k = 0; k < pairs; ++k) {
        const float r = std::sqrt(float(k + 1) / float(pairs));
        const glm::vec2 at = r * glm::vec2(std::cos(golden * float(k)), std::sin(golden * float(k)));
        taps.push_back({at.x, at.y, weight(r), 0.0f});
        taps.push_back({-at.x, -at.y, weight(r), 0.0f});
    }
    const float total = std::accumulate(taps.begin(), taps.end(), 0.0f, [](float s, const glm::vec4& t) { return s + t.z; });
    for (auto& t : taps) t.z /= total;
    return taps;
}

std::vector<glm::vec4> directTaps() { return {glm::vec4(0.0f, 0.0f, 1.0f, 0.0f)}; }

}  // namespace voxlux
