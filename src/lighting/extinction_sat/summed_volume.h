// The extinction summed-area table (Schlegel 2011, Sec. 3.1) in exact integer arithmetic.
// Each plane of the light grid is quantised to multiples of a power-of-two quantum chosen from the
// plane's maximum (values down to 2^-40 of it are exact), and prefix sums are kept modulo 2^96 in
// three 32-bit words. A box sum is a difference of prefix sums, exact in modular arithmetic as
// long as the box's own sum is below 2^96 quanta, which holds for any grid of fewer than 2^32
// cells. The kernel converts it to float once (src/lighting/extinction_sat/kernel/vx_sat.h). docs/accuracy-sat.md has the
// error bound.
#pragma once
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "lighting/light_grid.h"

namespace voxlux {

struct SummedVolume {
    glm::ivec3 dims{0};            // light-grid cells; entries are (dims + 1) per axis
    int planes = 0;
    glm::vec4 quantum{1.0f};       // per plane: the value of one integer unit
    std::vector<uint32_t> words;   // per plane, the low, middle and high word arrays; x fastest
    size_t planeEntries() const { return size_t(dims.x + 1) * (dims.y + 1) * (dims.z + 1); }
    uint32_t* word(int plane, int w) { return words.data() + (size_t(plane) * 3 + size_t(w)) * planeEntries(); }
};

// The quantum for a plane whose largest value is `max_value`: 2^(e - 63), where 2^e is the
// smallest power of two above max_value, so every cell is below 2^63 quanta.
float satQuantum(float max_value);

// The quantised cells alone (entry (x+1, y+1, z+1) holds cell (x, y, z), the faces zero), before
// any prefix sum: what the GL backend uploads and scans.
void quantizeLightGrid(const LightGrid& grid, SummedVolume& sat);

// The whole table on the CPU: quantisation and the three prefix sums fused slice by slice, so that
// beyond the cache only the grid is read and the table written once.
void buildSummedVolume(const LightGrid& grid, SummedVolume& sat);

}  // namespace voxlux
