#include "render/mesh_rays.h"

#include <cstring>
#include <limits>
#include <stdexcept>

#include <embree3/rtcore.h>

namespace voxlux {

struct MeshRays::Bvh {
    RTCScene scene = nullptr;
    ~Bvh() {
        if (scene) rtcReleaseScene(scene);
    }
};

namespace {

// One Embree device for the process: making one starts its threads, which costs more than a
// small mesh's BVH.
RTCDevice sharedDevice() {
    static const RTCDevice device = rtcNewDevice(nullptr);
    if (!device) throw std::runtime_error("Embree: no device (error " + std::to_string(int(rtcGetDeviceError(nullptr))) + ")");
    return device;
}

// Embree reports its failures through the device; voxlux's are then defects (out of memory aside).
void check(RTCDevice device, const char* what) {
    if (const RTCError e = rtcGetDeviceError(device); e != RTC_ERROR_NONE)
        throw std::runtime_error(std::string("Embree: ") + what + " failed (error " + std::to_string(int(e)) + ")");
}

}  // namespace

MeshRays::MeshRays(const std::vector<const TriangleMesh*>& meshes, const std::vector<glm::mat4>& placements) : bvh_(std::make_unique<Bvh>()) {
    const RTCDevice device = sharedDevice();
    bvh_->scene = rtcNewScene(device);
    for (size_t m = 0; m < meshes.size(); ++m) {
        const TriangleMesh& mesh = *meshes[m];
        RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
        auto* points = static_cast<float*>(
            rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), mesh.points.size()));
        auto* triangles = static_cast<unsigned*>(
            rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), mesh.triangles.size()));
        check(device, "a mesh's buffers");
        for (size_t p = 0; p < mesh.points.size(); ++p) {
            const glm::vec3 world = glm::vec3(placements[m] * glm::vec4(mesh.points[p], 1.0f));
            std::memcpy(points + 3 * p, &world[0], 3 * sizeof(float));
        }
        std::memcpy(triangles, mesh.triangles.data(), mesh.triangles.size() * sizeof(glm::uvec3));
        rtcCommitGeometry(geometry);
        rtcAttachGeometry(bvh_->scene, geometry);
        rtcReleaseGeometry(geometry);
    }
    rtcCommitScene(bvh_->scene);
    check(device, "building the BVH");
}

MeshRays::~MeshRays() = default;

float MeshRays::nearestHit(const glm::vec3& origin, const glm::vec3& dir) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit hit{};
    hit.ray.org_x = origin.x;
    hit.ray.org_y = origin.y;
    hit.ray.org_z = origin.z;
    hit.ray.dir_x = dir.x;
    hit.ray.dir_y = dir.y;
    hit.ray.dir_z = dir.z;
    hit.ray.tnear = 0.0f;
    hit.ray.tfar = std::numeric_limits<float>::infinity();
    hit.ray.mask = ~0u;
    hit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(bvh_->scene, &context, &hit);
    return hit.hit.geomID == RTC_INVALID_GEOMETRY_ID ? std::numeric_limits<float>::infinity() : hit.ray.tfar;
}

}  // namespace voxlux
