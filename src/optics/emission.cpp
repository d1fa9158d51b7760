#include "optics/emission.h"

#include <limits>

#include "optics/blackbody.h"
#include "vx_prelude.h"

namespace voxlux {
namespace {

// Linear between the points, clamped at the ends.
glm::vec3 rampColor(const std::vector<RampPoint>& ramp, float value) {
    if (value <= ramp.front().value) return ramp.front().color;
    for (size_t i = 1; i < ramp.size(); ++i)
        if (value <= ramp[i].value) {
            const RampPoint &a = ramp[i - 1], &b = ramp[i];
            return glm::mix(a.color, b.color, (value - a.value) / (b.value - a.value));
        }
    return ramp.back().color;
}

// XYZ radiance at `kelvin`, 0 below the cutoff. `norm` is the luminance brought to `intensity`:
// the temperature's own (luminance normalisation) or the reference temperature's (physical).
glm::dvec3 blackbody(const EmissionSource& s, double kelvin) {
    if (kelvin < s.cutoff || !(kelvin > 0.0)) return glm::dvec3(0.0);
    const glm::dvec3 xyz = blackbodyXYZ(kelvin);
    const double norm = s.normalization == BlackbodyNormalization::Luminance ? xyz.y
                                                                            : blackbodyXYZ(s.reference_temperature).y;
    // Far below visible temperatures Planck's radiance underflows: nothing to normalise.
    if (!(xyz.y > 0.0)) return glm::dvec3(0.0);
    return xyz * (double(s.intensity) / norm);
}

}  // namespace

glm::vec3 emissionRadiance(const EmissionSource& s, float value, const glm::mat3& xyz_to_working) {
    switch (s.kind) {
        case EmissionKind::Constant: return value * s.color * s.intensity;
        case EmissionKind::Ramp: return rampColor(s.ramp, value) * s.intensity;
        case EmissionKind::Blackbody: break;
    }
    const double kelvin = double(value) * s.temperature_scale + s.temperature_offset;
    return xyz_to_working * glm::vec3(blackbody(s, kelvin));
}

EmissionTable bakeEmission(const EmissionSource& source, float grid_max, const glm::mat3& xyz_to_working) {
    constexpr int n = VX_EMISSION_LUT_SIZE;
    EmissionTable t;
    t.rows.resize(n);
    int first = n;  // the first row that emits
    for (int i = 0; i < n; ++i) {
        // At most the float maximum: a grid value of 1e6 at intensity 3e38 is no infinite row.
        const glm::vec3 rgb = glm::min(emissionRadiance(source, grid_max * float(i) / float(n - 1), xyz_to_working),
                                       glm::vec3(std::numeric_limits<float>::max()));
        t.rows[size_t(i)] = glm::vec4(rgb, 0.0f);
        if (first == n && rgb != glm::vec3(0.0f)) first = i;
    }
    // Values up to the row before the first emitting one interpolate between zero rows.
    constexpr float inf = std::numeric_limits<float>::infinity();
    t.threshold = first == n ? inf : first == 0 ? -inf : grid_max * float(first - 1) / float(n - 1);
    return t;
}

}  // namespace voxlux
