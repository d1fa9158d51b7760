// Which world axis is up in a cache, and which side faces the default camera, as the file says.
// OpenVDB has no up-axis field, so this reads what each writer leaves: voxlux's importer writes
// `up_axis` and `front_axis` on a scan's grid (a NIfTI or DICOM scan is RAS: z up, the face toward
// +y); Blender writes Z-up domain-local grids (Mantaflow's `file_base_resolution` on every grid since
// 2.82, `creator` "Blender/..." or `is_local_space` without a creator in the older smoke cache);
// Houdini, EmberGen and OpenVDB's own tools are Y-up. Costs a few metadata lookups.
#pragma once
#include <optional>
#include <string>

#include <glm/glm.hpp>

#include <openvdb/openvdb.h>

namespace voxlux {

struct UpAxisGuess {
    int axis = 1;            // 0 x, 1 y, 2 z: the world axis along up
    std::string reason;      // what in the file said so, for `info` and the quick form's note
    glm::mat3 frame{1.0f};   // the default view: right, up and back (toward the camera), as upFrame
};

UpAxisGuess detectUpAxis(const openvdb::MetaMap& file_metadata, const openvdb::MetaMap& grid_metadata);

// The world axis `up_axis` (0 x, 1 y, 2 z) as the camera frame's up, and the axes of a right-handed
// frame around it: right, up and back (towards a front-facing camera). Y-up is (x, y, z); Z-up, as
// Blender's, is (x, z, -y).
glm::mat3 upFrame(int up_axis);

// "x", "-y", ...: a signed world axis as the `up_axis` and `front_axis` metadata write it; nullopt
// for anything else.
std::optional<glm::vec3> parseSignedAxis(const std::string& text);
std::string signedAxisName(glm::vec3 axis);

// The view frame with `up` up, seen from the `front` side (perpendicular to up): right, up, back.
glm::mat3 viewFrame(glm::vec3 up, glm::vec3 front);

}  // namespace voxlux
