// Fuzzes the shot-camera readers (camera.file): the first byte picks the kind (a Nuke .chan, a
// glTF, a binary glTF or an FBX scene read with assimp), the rest is the file; the camera is then
// posed between and beyond its keys. Bad input must throw InputError; anything else is a defect.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "core/error.h"
#include "scene/camera.h"
#include "scene/camera_file.h"
#include "scene/chan_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size == 0) return 0;
    const std::string bytes(reinterpret_cast<const char*>(data + 1), size - 1);
    try {
        voxlux::Camera camera;
        const char* kinds[] = {"chan", "gltf", "glb", "fbx"};
        const std::string kind = kinds[data[0] % 4];
        if (kind == "chan") {
            const voxlux::ChanTrack track = voxlux::parseChan(bytes, "fuzz.chan");
            voxlux::CameraFile f;
            f.pose.keys = track.keys;
            f.pose.rotate_order = voxlux::RotateOrder::Zxy;
            f.vertical_fov = track.vertical_fov;
            camera.file = f;
        } else {
            camera.file = voxlux::parseAssimpCamera(bytes, kind, "fuzz." + kind, "");
        }
        for (const double frame : {-1e9, 0.5, 1.0, 1e9}) {
            const voxlux::Camera posed = voxlux::posedCamera(camera, frame);
            const glm::mat4 m = voxlux::cameraToWorld(posed);
            for (int c = 0; c < 4; ++c)
                for (int r = 0; r < 4; ++r)
                    if (!std::isfinite(m[c][r])) std::abort();   // a finite camera file poses finitely
            if (!(posed.fov > 0.0f && posed.fov < 180.0f)) std::abort();
        }
    } catch (const voxlux::InputError&) {
    }
    return 0;
}
