// Shot cameras from other packages (camera.file, src/scene/camera_file.h): a glTF camera exported
// from a known pose, under a parent node, reproduces the JSON camera's camera-to-world (and so its
// worldToCamera) to 1e-6 and its field of view; a Nuke .chan animates the camera frame by frame in
// its rotate order, its field of view with it; focal length and film back give the field of view;
// a render through the file's camera is the render through the same camera written as JSON; bad
// camera files and keys are refused by name.
#include <cstdio>
#include <filesystem>
#include <fstream>

#include <glm/gtc/matrix_transform.hpp>

#include "scene/camera.h"
#include "scene/camera_file.h"
#include "scene/scene_json.h"
#include "test_support.h"

namespace voxlux::test {
namespace {

void writeText(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

// A glTF scene whose camera node `name` hangs under a parent moved by `parent` and has the local
// matrix `local` (column-major, as glTF's), with vertical field of view `yfov` radians.
std::string gltfCamera(const glm::mat4& parent, const glm::mat4& local, float yfov, const std::string& name = "shotCam") {
    const auto matrix = [](const glm::mat4& m) {
        std::string out = "[";
        char number[32];
        for (int i = 0; i < 16; ++i) {
            std::snprintf(number, sizeof number, "%.9g", double(m[i / 4][i % 4]));   // every digit of a float
            out += (i ? ", " : "") + std::string(number);
        }
        return out + "]";
    };
    return R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
 "nodes": [{"name": "rig", "matrix": )" + matrix(parent) + R"(, "children": [1]},
           {"name": ")" + name + R"(", "camera": 0, "matrix": )" + matrix(local) + R"(}],
 "cameras": [{"name": ")" + name + R"(", "type": "perspective", "perspective": {"yfov": )" + std::to_string(double(yfov)) +
           R"(, "aspectRatio": 1.5, "znear": 0.1}}]})";
}

// The JSON camera the files below are exported from.
Camera knownPose() {
    Camera c;
    c.position = glm::vec3(1.5f, 2.0f, 6.0f);
    c.look_at = glm::vec3(0.0f, 0.5f, 0.0f);
    c.up = glm::vec3(0.0f, 1.0f, 0.0f);
    c.fov = 35.0f;
    return c;
}

TEST(CameraFile, AGltfCameraReproducesTheJsonCamera) {
    const std::string dir = tempDir("camera-gltf");
    const Camera json = knownPose();
    const glm::mat4 camera_to_world = cameraToWorld(json);
    const glm::mat4 parent = glm::translate(glm::mat4(1.0f), glm::vec3(0.25f, -1.0f, 2.0f));
    writeText(dir + "/layout.gltf", gltfCamera(parent, glm::inverse(parent) * camera_to_world, glm::radians(json.fov)));
    Camera from_file;
    from_file.file = readCameraFile(dir + "/layout.gltf", "", RotateOrder::Zxy);
    EXPECT_EQ(from_file.file->name, "shotCam");
    const Camera posed = posedCamera(from_file, 7.0);
    EXPECT_LE(largestDifference(cameraToWorld(posed), camera_to_world), 1e-6f);
    EXPECT_LE(largestDifference(glm::inverse(cameraToWorld(posed)), glm::inverse(camera_to_world)), 1e-6f);   // worldToCamera
    EXPECT_NEAR(posed.fov, json.fov, 1e-4f);
}

TEST(CameraFile, AChanAnimatesTheCameraFrameByFrame) {
    const std::string dir = tempDir("camera-chan");
    // Nuke's camera export: frame, translate, rotate (degrees, zxy), vertical field of view.
    writeText(dir + "/shot.chan", "1 0 1 5 -10 20 0 30\n11 2 1 5 -5 40 10 50\n");
    Camera c;
    c.file = readCameraFile(dir + "/shot.chan", "", RotateOrder::Zxy);
    const auto expected = [](glm::vec3 t, glm::vec3 r) {
        glm::mat4 m(rotationMatrix(r, RotateOrder::Zxy));
        m[3] = glm::vec4(t, 1.0f);
        return m;
    };
    EXPECT_LE(largestDifference(cameraToWorld(posedCamera(c, 1.0)), expected({0, 1, 5}, {-10, 20, 0})), 1e-6f);
    EXPECT_LE(largestDifference(cameraToWorld(posedCamera(c, 6.0)), expected({1, 1, 5}, {-7.5f, 30, 5})), 1e-6f);
    EXPECT_LE(largestDifference(cameraToWorld(posedCamera(c, 20.0)), expected({2, 1, 5}, {-5, 40, 10})), 1e-6f);   // held
    EXPECT_FLOAT_EQ(posedCamera(c, 1.0).fov, 30.0f);
    EXPECT_FLOAT_EQ(posedCamera(c, 6.0).fov, 40.0f);
    EXPECT_FLOAT_EQ(posedCamera(c, 0.0).fov, 30.0f);
    // Rotation order zxy turns about z first: a pure y turn of 90 degrees looks along -x.
    writeText(dir + "/turn.chan", "1 0 0 0 0 90 0\n");
    Camera turn;
    turn.file = readCameraFile(dir + "/turn.chan", "", RotateOrder::Zxy);
    EXPECT_LE(glm::length(glm::vec3(cameraToWorld(posedCamera(turn, 1.0))[2]) - glm::vec3(1, 0, 0)), 1e-6f);   // back = +x
    EXPECT_FLOAT_EQ(posedCamera(turn, 1.0).fov, Camera{}.fov);   // no lens in the file: the scene's
}

TEST(CameraFile, FocalLengthAndFilmBackGiveTheFieldOfView) {
    const Scene s = parseScene(R"({"volume": {"path": "a.vdb"}, "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0],
                                   "focal_length": 50, "film_back": [36, 24]}})", "shot.json", "/shots");
    EXPECT_NEAR(posedCamera(*s.camera, 0.0).fov, 2.0 * glm::degrees(std::atan(24.0 / 100.0)), 1e-4);
    const Scene back = sceneFromJson(sceneToJson(s), "back.json", "/shots");
    EXPECT_FLOAT_EQ(back.camera->focal_length, 50.0f);
    EXPECT_EQ(back.camera->film_back, glm::vec2(36.0f, 24.0f));
}

TEST(CameraFile, ARenderThroughTheFileCameraIsTheRenderThroughTheJsonOne) {
    const std::string dir = tempDir("camera-render");
    const std::string ball = writeBall(dir);
    Camera json;
    json.position = glm::vec3(1.0f, 1.5f, 6.0f);
    json.look_at = glm::vec3(0.0f);
    json.fov = 30.0f;
    writeText(dir + "/layout.gltf", gltfCamera(glm::mat4(1.0f), cameraToWorld(json), glm::radians(json.fov)));
    const std::string scene = R"({"volume": {"path": ")" + ball + R"("}, "render": {"resolution": [24, 16], "backend": "cpu"},
                                  "lights": [{"direction": [0.3, -1, -0.4], "intensity": 3}])";
    Scene by_file = parseScene(scene + R"(, "camera": {"file": "layout.gltf"}})", "shot.json", dir);
    Scene by_json = parseScene(scene + "}", "shot.json", dir);
    by_json.camera = json;
    const RenderImage a = renderScene(by_file), b = renderScene(by_json);
    float largest = 0.0f, peak = 0.0f;
    for (size_t i = 0; i < a.pixels.size(); ++i) {
        largest = std::max(largest, glm::length(a.pixels[i].rgba - b.pixels[i].rgba));
        peak = std::max(peak, b.pixels[i].rgba.w);
    }
    EXPECT_GT(peak, 0.5f);   // the ball is in view
    EXPECT_LE(largest, 1e-4f);   // the same camera to float rounding of its matrix
}

TEST(CameraFile, BadCameraFilesAndKeysAreRefusedByName) {
    const std::string dir = tempDir("camera-errors");
    writeText(dir + "/shot.chan", "1 0 1 5 -10 20 0 30\n");
    writeText(dir + "/empty.gltf", R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"name": "n"}]})");
    writeText(dir + "/layout.gltf", gltfCamera(glm::mat4(1.0f), cameraToWorld(knownPose()), 0.6f));
    writeText(dir + "/broken.gltf", "{\"asset\": ");
    writeText(dir + "/triangle.gltf", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");   // an OBJ: no other format's importer is tried
    const auto error = [&](const std::string& camera) {
        return inputErrorOf([&] { parseScene(R"({"volume": {"path": "a.vdb"}, "camera": )" + camera + "}", "shot.json", dir); });
    };
    EXPECT_EQ(error(R"({"file": "missing.chan"})"), dir + "/missing.chan: cannot open .chan file");
    EXPECT_EQ(error(R"({"file": "missing.gltf"})"), dir + "/missing.gltf: cannot open camera file");
    EXPECT_EQ(error(R"({"file": "shot.abc"})"), dir + "/shot.abc: not a camera file voxlux reads (expected .chan, .gltf, .glb or .fbx)");
    EXPECT_EQ(error(R"({"file": "empty.gltf"})"), dir + "/empty.gltf: has no camera");
    EXPECT_EQ(error(R"({"file": "layout.gltf", "name": "witness"})"), dir + "/layout.gltf: has no camera named 'witness' (its cameras are 'shotCam')");
    EXPECT_EQ(error(R"({"file": "broken.gltf"})").rfind(dir + "/broken.gltf: not a .gltf file assimp reads (", 0), 0u);
    EXPECT_EQ(error(R"({"file": "triangle.gltf"})"), dir + "/triangle.gltf: not a .gltf file assimp reads (no importer of its format recognises it)");
    EXPECT_EQ(error(R"({"file": "shot.chan", "position": [0, 0, 1]})"), "shot.json: /camera/position: comes from the camera file (camera.file)");
    EXPECT_EQ(error(R"({"file": "shot.chan", "fov": 30})"), "shot.json: /camera/fov: comes from the camera file, which has a lens");
    EXPECT_EQ(error(R"({"file": "shot.chan", "name": "cam"})"), "shot.json: /camera/name: picks a camera of a glTF or FBX file; a .chan holds one");
    EXPECT_EQ(error(R"({"file": "layout.gltf", "rotate_order": "xyz"})"),
              "shot.json: /camera/rotate_order: turns a .chan's rotations; a glTF or FBX camera has its matrix");
    EXPECT_EQ(error(R"({"position": [0, 0, 5], "look_at": [0, 0, 0], "fov": 30, "focal_length": 35})"),
              "shot.json: /camera/focal_length: gives the field of view, which fov gives too: set one of them");
    EXPECT_EQ(error(R"({"position": [0, 0, 5], "look_at": [0, 0, 0], "film_back": [36, 24]})"), "shot.json: /camera/film_back: goes with focal_length");
    EXPECT_EQ(error(R"({"position": [0, 0, 5], "look_at": [0, 0, 0], "name": "cam"})"), "shot.json: /camera/name: goes with camera.file");
    writeText(dir + "/wide.chan", "1 0 1 5 -10 20 0 180\n");
    EXPECT_EQ(error(R"({"file": "wide.chan"})"), dir + "/wide.chan: line 1: field of view 180 does not lie in (0, 180) degrees");
}

}  // namespace
}  // namespace voxlux::test
