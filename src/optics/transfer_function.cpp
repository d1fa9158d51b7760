#include "optics/transfer_function.h"

#include <algorithm>
#include <cmath>

#include "vx_prelude.h"

namespace voxlux {

std::vector<glm::vec4> bakeTransfer(const std::vector<TransferPoint>& tf) {
    std::vector<glm::vec4> lut(VX_TF_LUT_SIZE, glm::vec4(1.0f));
    if (tf.empty()) return lut;
    const float lo = tf.front().value, hi = tf.back().value;
    size_t seg = 0;
    for (int i = 0; i < VX_TF_LUT_SIZE; ++i) {
        float v = lo + (hi - lo) * float(i) / float(VX_TF_LUT_SIZE - 1);
        while (seg + 2 < tf.size() && v > tf[seg + 1].value) ++seg;
        const auto& a = tf[seg];
        const auto& b = tf[seg + 1];
        float f = std::clamp((v - a.value) / (b.value - a.value), 0.0f, 1.0f);
        lut[i] = glm::vec4(glm::mix(a.albedo, b.albedo, f), a.extinction + (b.extinction - a.extinction) * f);
    }
    return lut;
}

float maxTransferExtinction(const std::vector<glm::vec4>& table, const std::vector<TransferPoint>& points, float lo,
                            float hi) {
    const float d0 = points.front().value, d1 = points.back().value;
    auto index = [&](float v) { return std::clamp((v - d0) / (d1 - d0), 0.0f, 1.0f) * float(VX_TF_LUT_SIZE - 1); };
    const int first = int(std::floor(index(lo)));
    const int last = std::min(int(std::ceil(index(hi))), VX_TF_LUT_SIZE - 1);
    float m = 0.0f;
    for (int i = first; i <= last; ++i) m = std::max(m, table[size_t(i)].w);
    return m;
}

}  // namespace voxlux
