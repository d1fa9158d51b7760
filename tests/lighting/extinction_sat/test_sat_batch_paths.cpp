// The light passes' row batches (vx_sat.h's VxSatRow and VxConeRow, run by
// src/lighting/extinction_sat/cpu_light_pass.cpp) against the per-cell kernel they stand in for
// (vx_ambient_tau and vx_cone_tau), cell by cell, on the CPU alone (tests/lighting/batch_paths.h).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "lighting/batch_paths.h"
#include "lighting/extinction_sat/cpu_light_pass.h"
#include "lighting/extinction_sat/kernel/cpu_sat_kernel.h"
#include "lighting/extinction_sat/summed_volume.h"
#include "lighting/light_grid.h"

namespace voxlux::test {
namespace {

// Every pass kind (AO from the extinction plane and from a bleeding plane, cones towards a
// directional light, a point light inside the grid and one outside), over cells the march needs
// (about two in three): the batched channel equals the per-cell query to float rounding, and
// cells not needed are left as they were.
TEST(BatchPaths, LightPassRowsMatchThePerCellQueries) {
    LightGrid grid;
    grid.dims = glm::ivec3(37, 29, 23);
    grid.planes = 4;
    grid.values = randomValues(grid.cells() * 4, 3.0f, 7);
    std::mt19937 rng(11);
    grid.needed.resize(grid.cells());
    for (auto& n : grid.needed) n = rng() % 3 != 0;
    SummedVolume sat;
    buildSummedVolume(grid, sat);
    const std::vector<kernel::VxLight> lights = {directionalLight({0.3f, -1.0f, 0.45f}), pointLight({12.3f, 20.7f, 9.1f}),
                                                 pointLight({-20.0f, 14.0f, 40.0f})};
    LightPass pass;
    pass.lights = &lights;
    pass.sat = &sat;
    pass.needed = &grid.needed;
    kernel::VxSatParams& S = pass.params;
    S.light_to_world = glm::mat4(1.0f);
    S.world_to_light = glm::mat4(1.0f);
    S.dims = grid.dims;
    S.planes = sat.planes;
    S.quantum = sat.quantum;
    S.cache_floats = 1;
    S.shells = 5;
    S.shell_radius = 6.0f;
    S.cell_world = 1.0f;
    S.cone_tan = std::tan(glm::radians(4.0f));
    S.cone_cuboids = 12;
    S.cone_growth = 0.15f;
    S.cone_growth_total = std::pow(1.15f, 12.0f);

    struct Case {
        const char* name;
        int light;
        int ao_plane;
    };
    for (const Case& c : {Case{"AO, extinction plane", -1, 0}, Case{"AO, bleeding plane", -1, 2},
                          Case{"cones, directional", 0, 0}, Case{"cones, point inside", 1, 0},
                          Case{"cones, point outside", 2, 0}}) {
        S.light = c.light;
        S.ao_plane = c.ao_plane;
        S.channel = 0;
        LightCache batched;
        batched.channels = 1;
        batched.values.assign(grid.cells(), -1.0f);
        fillLightChannelCpu(pass, batched);

        kernel::CpuSatKernel k;
        k.S = S;
        k.sat = sat.words;
        k.lights = lights;
        std::vector<float> per_cell(grid.cells(), -1.0f);
        for (int z = 0; z < grid.dims.z; ++z)
            for (int y = 0; y < grid.dims.y; ++y)
                for (int x = 0; x < grid.dims.x; ++x) {
                    const size_t cell = (size_t(z) * grid.dims.y + y) * grid.dims.x + x;
                    if (!grid.needed[cell]) continue;
                    per_cell[cell] = c.light < 0 ? k.vx_ambient_tau({x, y, z}, c.ao_plane)
                                                 : k.vx_cone_tau({x, y, z}, lights[size_t(c.light)]);
                }
        size_t untouched = 0, left = 0;
        for (size_t i = 0; i < per_cell.size(); ++i)
            if (!grid.needed[i]) ++untouched, left += batched.values[i] == -1.0f;
        EXPECT_EQ(left, untouched) << c.name;
        // Measured: bit-identical in every case (each lane adds the per-cell query's vx_sat_term,
        // in the same order); the bound leaves room for a compiler fusing a product differently.
        const double error = relativeError(batched.values, per_cell);
        std::printf("  light pass, %-22s max |batch - per cell| / peak %.2g\n", c.name, error);
        EXPECT_LE(error, 2e-7) << c.name;
    }
}

}  // namespace
}  // namespace voxlux::test
