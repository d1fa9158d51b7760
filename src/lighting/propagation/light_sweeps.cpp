#include "lighting/propagation/light_sweeps.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>

#include "lighting/propagation/kernel/cpu_propagation_kernel.h"

namespace voxlux {

std::vector<Sweep> sweepsFor(glm::vec3 flow, bool blend) {
    const glm::vec3 f = flow == glm::vec3(0.0f) ? glm::vec3(0.0f, 0.0f, 1.0f) : flow;
    kernel::CpuPropagationKernel k;
    std::vector<Sweep> out;
    for (int axis = 0; axis < 3; ++axis) {
        const int sign = f[axis] < 0.0f ? -1 : 1;
        const float w = k.vx_sweep_weight(f, axis, sign, blend);
        if (w > 0.0f) out.push_back({axis, sign, w});
    }
    // Principal first: the larger weight, and on a body diagonal's equal split the higher axis.
    std::sort(out.begin(), out.end(), [](const Sweep& a, const Sweep& b) {
        return a.weight != b.weight ? a.weight > b.weight : a.axis > b.axis;
    });
    return out;
}

std::vector<Sweep> pointLightSweeps(glm::vec3 at, glm::ivec3 dims, bool blend) {
    // A cell is weighted by a sweep only where its flow is within the sweep's pyramid: slope 1 to
    // the side for the principal axis, VX_PROP_MAX_SLOPE for a blended second axis. The pyramid
    // widens away from the light, so it meets the grid's cell centres if it meets them on the
    // farthest slice.
    const float slope = blend ? VX_PROP_MAX_SLOPE : 1.0f;
    std::vector<Sweep> out;
    for (int axis = 0; axis < 3; ++axis)
        for (int sign : {1, -1}) {
            const float reach = sign > 0 ? float(dims[axis]) - 0.5f - at[axis] : at[axis] - 0.5f;
            if (reach <= 0.0f) continue;
            bool meets = true;
            for (int side = 0; side < 3; ++side) {
                if (side == axis) continue;
                meets = meets && at[side] - slope * reach <= float(dims[side]) - 0.5f && at[side] + slope * reach >= 0.5f;
            }
            if (meets) out.push_back({axis, sign, 1.0f});
        }
    return out;
}

std::vector<Sweep> spotLightSweeps(const std::vector<Sweep>& sweeps, glm::vec3 direction, float cos_outer,
                                   const glm::mat3& world_to_grid) {
    const glm::mat3 grid_to_world = glm::inverse(world_to_grid);
    const glm::vec3 d = glm::normalize(direction);
    auto inCone = [&](glm::vec3 grid_dir) { return glm::dot(glm::normalize(grid_to_world * grid_dir), d) > cos_outer - 1e-4f; };
    // Directions on the cone's rim, in grid space.
    const glm::vec3 side = glm::normalize(glm::cross(d, std::abs(d.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0)));
    const glm::vec3 up = glm::cross(d, side);
    const float sin_outer = std::sqrt(std::max(0.0f, 1.0f - cos_outer * cos_outer));
    std::vector<glm::vec3> rim;
    for (int k = 0; k < 64; ++k) {
        const float a = 2.0f * float(M_PI) * float(k) / 64.0f;
        rim.push_back(world_to_grid * (cos_outer * d + sin_outer * (std::cos(a) * side + std::sin(a) * up)));
    }
    kernel::CpuPropagationKernel k;
    std::vector<Sweep> out;
    for (const Sweep& s : sweeps) {
        // The cone meets the sweep's pyramid if the pyramid's axis or one of its edges lies in the
        // cone, or a rim direction lies in the pyramid (the cone is convex, and so is the pyramid).
        bool meets = false;
        for (int corner = 0; corner < 5 && !meets; ++corner) {
            glm::vec3 g(0.0f);
            g[s.axis] = float(s.sign);
            if (corner > 0) {
                g[k.vx_axis_u(s.axis)] = corner & 1 ? 1.0f : -1.0f;
                g[k.vx_axis_v(s.axis)] = corner & 2 ? 1.0f : -1.0f;
            }
            meets = inCone(g);
        }
        for (size_t r = 0; r < rim.size() && !meets; ++r) meets = k.vx_sweep_weight(rim[r], s.axis, s.sign, false) > 0.0f;
        if (meets) out.push_back(s);
    }
    return out;
}

namespace {

kernel::VxTap tap(glm::vec2 offset, float weight) {
    kernel::VxTap t{};
    t.offset = offset;
    t.weight = weight;
    return t;
}

}  // namespace

std::vector<kernel::VxTap> blurTaps(const Indirect& in) {
    const float tan_half = std::tan(glm::radians(0.5f * in.angle));
    kernel::CpuPropagationKernel k;   // for its phase function
    auto weight = [&](float r) {
        const float cos_a = 1.0f / std::sqrt(1.0f + r * r * tan_half * tan_half);
        if (in.phase == BlurPhase::Phong) return std::pow(cos_a, in.exponent);
        return k.vx_phase_hg(cos_a, in.g);   // the taps are normalised below: 4 pi cancels
    };
    std::vector<kernel::VxTap> taps;
    if (in.samples % 2 == 1) taps.push_back(tap(glm::vec2(0.0f), weight(0.0f)));
    // Opposite pairs on a Vogel spiral: even coverage of the disc, and a weighted centre exactly at
    // the light's own direction, so the blur never drifts the light sideways.
    const int pairs = in.samples / 2;
    const float golden = 2.39996323f;  // radians
    for (int k = 0; k < pairs; ++k) {
        const float r = std::sqrt(float(k + 1) / float(pairs));
        const glm::vec2 at = r * glm::vec2(std::cos(golden * float(k)), std::sin(golden * float(k)));
        taps.push_back(tap(at, weight(r)));
        taps.push_back(tap(-at, weight(r)));
    }
    const float total = std::accumulate(taps.begin(), taps.end(), 0.0f, [](float s, const kernel::VxTap& t) { return s + t.weight; });
    for (auto& t : taps) t.weight /= total;
    return taps;
}

std::vector<kernel::VxTap> directTaps() { return {tap(glm::vec2(0.0f), 1.0f)}; }

}  // namespace voxlux
