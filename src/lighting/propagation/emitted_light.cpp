#include "lighting/propagation/emitted_light.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/huge_pages.h"

namespace voxlux {
namespace {

constexpr float kFourPi = float(4.0 * M_PI);
// The largest ratio of successive orders the series is summed with: its sum stays finite (at most
// 100 times the second order) in a medium that absorbs nothing.
constexpr float kMaxRatio = 0.99f;

// Sweeps the sources `input` (RGB per world unit, per cell of g) through the extinction from the
// six axis directions into `volume`'s values (3 per cell), 4 pi / 6 times each sweep: the
// fluence, with each face of the cube carrying a sixth of the sphere. Q: the indirect sweeps'.
void sweepSources(const std::vector<float>& input, kernel::VxPropParams Q, const SweepGrid& g, const KernelInputs& inputs,
                  PropagationPasses& device, IlluminationVolume& volume, LightUpdate& report) {
    Q.source_sweep = 1;
    Q.source_is_position = 0;
    Q.per_cell_flow = 0;
    Q.eye_sweep = 0;
    Q.atten = glm::vec3(1.0f);   // the extinction's own depth, whatever the transport colours
    Q.transport_planes = 0;
    Q.tint = glm::vec3(1.0f);
    Q.weight = kFourPi / 6.0f;
    Q.light = kernel::VxLight{};
    assignInHugePages(volume.values, input.size(), 0.0f);
    PropagationPass pass;
    pass.march = &inputs.params;
    pass.noise = &inputs.noise;
    pass.sigma = g.sigma;
    pass.sigma_generation = g.sigma_generation;
    pass.offset = 0;
    pass.input = &input;
    for (int axis = 0; axis < 3; ++axis)
        for (int sign : {1, -1}) {
            Q.axis = axis;
            Q.direction = sign;
            Q.source = glm::vec3(0.0f);
            Q.source[axis] = float(sign);   // the flow: along the axis
            pass.sweeps = {Q};
            device.propagate(pass, volume);
            report.sweeps += 1;
            report.passes += 1;
            report.slices += g.dims[axis];
        }
}

}  // namespace

double emittedLightCost(const SweepGrid& g) {
    if (!g.emission) return 0.0;
    // Per order: the x axis both ways (slice-major copies) and the y and z axes both ways.
    const double sweep = SweepCost::kPass + SweepCost::kIndirect;
    return double(g.dims.x) * g.dims.y * g.dims.z * (kEmittedLightSweeps / 6) * (2.0 * sweep * SweepCost::kXAxis + 4.0 * sweep);
}

bool emissionLightsTheMedium(const Scene& s) {
    return emits(s) && s.effects.indirect && s.effects.shadows == ShadowMethod::Propagation &&
           s.render.method == RenderMethod::March;
}

void addEmittedLight(const SweepGrid& grid, const Material& material, const kernel::VxPropParams& indirect,
                     const KernelInputs& inputs, PropagationPasses& device, size_t block_first, IlluminationVolume& volume, LightUpdate& report) {
    if (!grid.emission || std::all_of(grid.emission->begin(), grid.emission->end(), [](float e) { return e <= 0.0f; }))
        return;
    const std::vector<float>& sigma = *grid.sigma;
    float* block = volume.values.data() + block_first + volume.indirectOffset();
    // Sums and products in double, capped at the float maximum: no order, and no sum of them, is
    // ever infinite, so no NaN follows from one (docs/scene.md, "Extreme values").
    auto capped = [](double v) { return float(std::min(v, double(std::numeric_limits<float>::max()))); };
    IlluminationVolume first, second;   // the fluence of light scattered 0 and 1 times
    sweepSources(*grid.emission, indirect, grid, inputs, device, first, report);
    // The light order 1 scatters: order 2's source.
    std::vector<float> scattered(first.values.size());
    // The scattering coefficient of channel i % 3 of cell i / 3 (sigma's first plane: the
    // extinction), and the albedo there.
    const auto scattering = [&](size_t i) {
        return grid.scattering ? double((*grid.scattering)[i]) : double(material.albedo[int(i % 3)]) * sigma[i / 3];
    };
    const auto albedo = [&](size_t i) {
        return !grid.scattering ? double(material.albedo[int(i % 3)]) : sigma[i / 3] > 0.0f ? scattering(i) / sigma[i / 3] : 0.0;
    };
    for (size_t i = 0; i < first.values.size(); ++i) scattered[i] = capped(scattering(i) * first.values[i] / kFourPi);
    sweepSources(scattered, indirect, grid, inputs, device, second, report);
    // The orders after: a geometric series at the ratio of the second order to the first, per cell
    // and channel, at most the albedo (the ratio the orders tend to in an unbounded medium).
    for (size_t i = 0; i < first.values.size(); ++i) {
        const double limit = std::min(albedo(i), double(kMaxRatio));
        const double ratio = first.values[i] > 0.0f ? std::min(double(second.values[i]) / first.values[i], limit) : 0.0;
        block[i] = capped(double(block[i]) + first.values[i] + second.values[i] / (1.0 - ratio));
    }
}

}  // namespace voxlux
