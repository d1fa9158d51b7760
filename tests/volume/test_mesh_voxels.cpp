// A holdout mesh's shadowing cells (src/volume/mesh_voxels.h): a quad through voxel centres is a
// shell of coverage 1 on it, 1/2 a voxel away, 0 (and inactive) from a voxel and a half on, cut to
// the clip box grown by that reach; a mesh wholly outside the box makes no cells.
#include <glm/gtc/matrix_transform.hpp>

#include "scene/mesh_file.h"
#include "test_support.h"
#include "volume/mesh_voxels.h"

namespace voxlux::test {
namespace {

TriangleMesh quadAtZ(float z, float half) {
    TriangleMesh quad;
    quad.points = {{-half, -half, z}, {half, -half, z}, {half, half, z}, {-half, half, z}};
    quad.triangles = {{0, 1, 2}, {0, 2, 3}};
    return quad;
}

TEST(MeshVoxels, AQuadIsAShellOfCoverageCutToTheBox) {
    const LoadedVolume cells = voxelisedMesh(quadAtZ(0.0f, 1.0f), glm::mat4(1.0f), 0.1f, glm::vec3(-0.5f), glm::vec3(0.5f), "quad.obj");
    EXPECT_EQ(voxelEdge(cells.index_to_world), 0.1f);
    const auto acc = cells.density->getConstAccessor();
    // The cell whose centre is at world (x, y, z) (index 0 sits at the grown box's corner).
    const auto at = [&](double x, double y, double z) { return cells.density->transform().worldToIndexCellCentered(openvdb::Vec3d(x, y, z)); };
    EXPECT_EQ(at(0.0, 0.0, 0.0), openvdb::Coord(7, 7, 7));   // the box grown by the shell's reach starts at -0.65: cell -0.7
    EXPECT_NEAR(acc.getValue(at(0.0, 0.0, 0.0)), 1.0f, 1e-5f);
    EXPECT_NEAR(acc.getValue(at(0.3, -0.2, 0.0)), 1.0f, 1e-5f);
    EXPECT_NEAR(acc.getValue(at(0.0, 0.0, 0.1)), 0.5f, 1e-4f);
    EXPECT_NEAR(acc.getValue(at(0.0, 0.0, -0.1)), 0.5f, 1e-4f);
    EXPECT_EQ(acc.getValue(at(0.0, 0.0, 0.2)), 0.0f);
    EXPECT_FALSE(acc.isValueOn(at(0.0, 0.0, 0.2)));
    // The box [-0.5, 0.5] grown by the shell's reach (0.15): x 0.6 is in, 0.7 is out.
    EXPECT_NEAR(acc.getValue(at(0.6, 0.0, 0.0)), 1.0f, 1e-5f);
    EXPECT_FALSE(acc.isValueOn(at(0.7, 0.0, 0.0)));
    EXPECT_EQ(acc.getValue(at(0.7, 0.0, 0.0)), 0.0f);
    // Far from the origin the indices stay the box's, and a placement past 1e9 is refused.
    const glm::mat4 far = glm::translate(glm::mat4(1.0f), glm::vec3(1e5f, 0.0f, 0.0f));
    const LoadedVolume moved = voxelisedMesh(quadAtZ(0.0f, 1.0f), far, 0.1f, glm::vec3(1e5f - 0.5f, -0.5f, -0.5f), glm::vec3(1e5f + 0.5f, 0.5f, 0.5f), "quad.obj");
    EXPECT_LT(moved.density->evalActiveVoxelBoundingBox().max().x(), 16);
    const glm::mat4 huge = glm::scale(glm::mat4(1.0f), glm::vec3(1e10f));
    EXPECT_EQ(inputErrorOf([&] { voxelisedMesh(quadAtZ(0.0f, 1.0f), huge, 0.1f, glm::vec3(-0.5f), glm::vec3(0.5f), "quad.obj"); }),
              "quad.obj: the holdout's transform places a point beyond +-1e9");
    // Placed 2 units up, the quad lies outside the box: no cells at all.
    const glm::mat4 up = glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 0.0f, 2.0f));
    EXPECT_EQ(voxelisedMesh(quadAtZ(0.0f, 1.0f), up, 0.1f, glm::vec3(-0.5f), glm::vec3(0.5f), "quad.obj").density->activeVoxelCount(), 0u);
}

}  // namespace
}  // namespace voxlux::test
