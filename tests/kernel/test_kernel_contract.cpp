// The CPU side of the kernel contract (cmake/kernel_contract.cmake): a lighting method's arrays
// reach CpuKernelData by their block names, as the GL backend binds them, and a march stage's block
// and arrays reach the march's kernel through makeKernelInputs.
#include <vector>

#include "kernel/cpu_kernel.h"
#include "test_support.h"

namespace voxlux::test {
namespace {

TEST(KernelContract, ArraysBindByTheirBlockNames) {
    kernel::CpuKernel k;
    const std::vector<float> cache = {1.0f, 2.0f, 3.0f};
    const std::vector<float> illum = {4.0f, 5.0f};
    EXPECT_TRUE(k.vx_bind_array("LightCache", cache.data(), cache.size() * sizeof(float)));
    EXPECT_TRUE(k.vx_bind_array("Illumination", illum.data(), illum.size() * sizeof(float)));
    EXPECT_FALSE(k.vx_bind_array("NoSuchBlock", cache.data(), sizeof(float)));
    EXPECT_EQ(k.cache.size, 3);
    EXPECT_EQ(k.vx_cache(2), 3.0f);
    EXPECT_EQ(k.illum.size, 2);
    EXPECT_EQ(k.vx_illum(1), 5.0f);
    // The arrays the march reads of the methods, which the GL backend uploads for every march.
    EXPECT_EQ(std::vector<std::string_view>(k.kLightingArrays.begin(), k.kLightingArrays.end()),
              (std::vector<std::string_view>{"LightCache", "Illumination"}));
}

TEST(KernelContract, AStageHandsTheMarchItsBlockAndArrays) {
    const Scene scene;
    const auto box = prepare(volumeFromGrid(boxGrid(openvdb::Coord(0), openvdb::Coord(7), 1.0f)), scene,
                             cameraAlong(glm::vec3(4.0f), glm::vec3(0, 0, -1), 20.0f, 30.0f));
    const std::vector<float> cache(8, 0.5f);
    MarchSources sources;
    sources.lighting.blocks.extinction_sat.cache_dims = glm::ivec3(2);
    sources.lighting.blocks.extinction_sat.cache_floats = 1;
    sources.lighting.setArray("LightCache", cache.data(), cache.size() * sizeof(float));
    const std::vector<float> newer(8, 0.25f);
    sources.lighting.setArray("LightCache", newer.data(), newer.size() * sizeof(float));   // a later stage's wins
    const KernelInputs in = makeKernelInputs(scene, box->atlas, box->pages, 0.0f, kXyzD65ToAcescg, sources);
    const kernel::CpuKernel k = bindCpuKernel(in);
    EXPECT_EQ(k.L.extinction_sat.cache_dims, glm::ivec3(2));
    ASSERT_EQ(k.cache.size, 8);
    EXPECT_EQ(k.vx_cache(0), 0.25f);
    // A block no stage set is zero: its method is off.
    EXPECT_EQ(k.L.propagation.illum_dims, glm::ivec3(0));
    EXPECT_EQ(k.illum.size, 0);
}

}  // namespace
}  // namespace voxlux::test
