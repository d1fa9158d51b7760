// Holdout meshes (holdouts[i].mesh, src/scene/mesh_file.h): an OBJ polygon becomes a fan of
// triangles at the file's coordinates; a glTF mesh is placed by its node and the node's parents;
// points, lines and empty files have no triangles; files are refused by name, and only their own
// format's importer reads them.
#include <fstream>

#include "core/error.h"
#include "scene/mesh_file.h"
#include "test_support.h"

namespace voxlux::test {
namespace {

TEST(MeshFile, AnObjPolygonIsAFanOfTriangles) {
    const std::string dir = tempDir("mesh-obj");
    std::ofstream(dir + "/pentagon.obj") << "# a pentagon\nv 0 0 0\nv 2 0 0\nv 3 1 0\nv 1 2 0\nv -1 1 0\nf 1 2 3 4 5\n";
    const TriangleMesh mesh = readMeshFile(dir + "/pentagon.obj");
    ASSERT_EQ(mesh.points.size(), 5u);
    EXPECT_EQ(mesh.points[2], glm::vec3(3.0f, 1.0f, 0.0f));
    EXPECT_EQ(mesh.triangles, (std::vector<glm::uvec3>{{0, 1, 2}, {0, 2, 3}, {0, 3, 4}}));
}

// One triangle (0,0,0), (1,0,0), (0,1,0) in a node scaled by 2 under a parent moved by (10, 0, 0).
TEST(MeshFile, AGltfMeshIsPlacedByItsNodes) {
    const std::string gltf = R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
 "nodes": [{"name": "set", "translation": [10, 0, 0], "children": [1]}, {"name": "wall", "scale": [2, 2, 2], "mesh": 0}],
 "meshes": [{"name": "wall", "primitives": [{"attributes": {"POSITION": 0}}]}],
 "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}],
 "bufferViews": [{"buffer": 0, "byteLength": 36}],
 "buffers": [{"byteLength": 36, "uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}]})";
    const TriangleMesh mesh = parseMeshFile(gltf, "gltf", "set.gltf");
    ASSERT_EQ(mesh.triangles.size(), 1u);
    const glm::uvec3 t = mesh.triangles[0];
    EXPECT_EQ(mesh.points[t.x], glm::vec3(10.0f, 0.0f, 0.0f));
    EXPECT_EQ(mesh.points[t.y], glm::vec3(12.0f, 0.0f, 0.0f));
    EXPECT_EQ(mesh.points[t.z], glm::vec3(10.0f, 2.0f, 0.0f));
}

TEST(MeshFile, BadFilesAreRefusedByName) {
    const std::string dir = tempDir("mesh-bad");
    std::ofstream(dir + "/lines.obj") << "v 0 0 0\nv 1 0 0\nl 1 2\n";
    std::ofstream(dir + "/far.obj") << "v 0 0 0\nv 1e10 0 0\nv 0 1 0\nf 1 2 3\n";
    std::ofstream(dir + "/triangle.fbx") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";   // an OBJ under another name
    EXPECT_EQ(inputErrorOf([&] { readMeshFile(dir + "/missing.obj"); }), dir + "/missing.obj: cannot open mesh file");
    EXPECT_EQ(inputErrorOf([&] { readMeshFile(dir + "/set.usd"); }), dir + "/set.usd: not a mesh file voxlux reads (expected .obj, .gltf, .glb or .fbx)");
    EXPECT_EQ(inputErrorOf([&] { readMeshFile(dir + "/lines.obj"); }), dir + "/lines.obj: has no triangles");
    EXPECT_EQ(inputErrorOf([&] { readMeshFile(dir + "/far.obj"); }), dir + "/far.obj: mesh 'defaultobject' has a point beyond +-1e9");
    EXPECT_EQ(inputErrorOf([&] { readMeshFile(dir + "/triangle.fbx"); }),
              dir + "/triangle.fbx: not a .fbx file assimp reads (no importer of its format recognises it)");
}

}  // namespace
}  // namespace voxlux::test
