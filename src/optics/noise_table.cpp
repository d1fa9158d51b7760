#include "optics/noise_table.h"

#include <algorithm>
#include <cstdint>

#include "kernel/kernel_types.h"

namespace voxlux {
namespace {

constexpr int N = VX_NOISE_SIZE;

// SplitMix64: a fixed, portable sequence (std:: distributions differ between library versions).
uint64_t splitMix(uint64_t& state) {
    uint64_t z = (state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

size_t texel(int x, int y, int z) { return (size_t((z + N) % N) * N + size_t((y + N) % N)) * N + size_t((x + N) % N); }

}  // namespace

std::vector<glm::vec4> makeNoiseTable(int seed) {
    std::vector<glm::vec4> a(size_t(N) * N * N), b(a.size());
    uint64_t state = uint64_t(uint32_t(seed)) * 0x2545f4914f6cdd1dull + 1;
    for (auto& t : a)
        for (int c = 0; c < 4; ++c) t[c] = float(double(splitMix(state) >> 11) * 0x1.0p-53 * 2.0 - 1.0);
    // [1 2 1] / 4 along each axis, wrapping.
    const glm::ivec3 axes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (const glm::ivec3& s : axes) {
        for (int z = 0; z < N; ++z)
            for (int y = 0; y < N; ++y)
                for (int x = 0; x < N; ++x)
                    b[texel(x, y, z)] = 0.25f * a[texel(x - s.x, y - s.y, z - s.z)] + 0.5f * a[texel(x, y, z)] +
                                        0.25f * a[texel(x + s.x, y + s.y, z + s.z)];
        std::swap(a, b);
    }
    // The blur narrows the range: stretch each component back to [-1, 1].
    glm::vec4 peak(0.0f);
    for (const auto& t : a) peak = glm::max(peak, glm::abs(t));
    for (auto& t : a) t /= glm::max(peak, glm::vec4(1e-6f));
    return a;
}

}  // namespace voxlux
