#include "io/exr_common.h"

#include <cmath>
#include <map>
#include <stdexcept>

#include <ImfFloatAttribute.h>
#include <ImfIntAttribute.h>
#include <ImfStandardAttributes.h>
#include <ImfStringAttribute.h>
#include <ImfStringVectorAttribute.h>

namespace voxlux {
namespace {

Imath::M44f toImath(const glm::mat4& m) {
    Imath::M44f out;  // Imath multiplies row vectors; glm's m[c][r] holds the same numbers
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) out[i][j] = m[i][j];
    return out;
}

}  // namespace

Imf::Header voxluxExrHeader(int width, int height, const ExrMetadata& meta) {
    Imf::Header header(width, height);
    header.insert("voxlux/version", Imf::StringAttribute(VOXLUX_VERSION));
    header.insert("voxlux/sceneHash", Imf::StringAttribute(meta.scene_hash));
    if (meta.frame) header.insert("voxlux/frame", Imf::IntAttribute(*meta.frame));
    for (const auto& [stage, seconds] : meta.stage_seconds)
        header.insert("voxlux/seconds/" + stage, Imf::FloatAttribute(float(seconds)));
    Imf::addWorldToCamera(header, toImath(meta.world_to_camera));
    Imf::addWorldToNDC(header, toImath(meta.world_to_ndc));
    if (!meta.color_space.empty()) {
        header.insert("oiio:ColorSpace", Imf::StringAttribute(meta.color_space));
        header.insert("voxlux/colorSpace", Imf::StringAttribute(meta.color_space));
    }
    if (!meta.color_config.empty()) header.insert("voxlux/config", Imf::StringAttribute(meta.color_config));
    header.insert("voxlux/exposure", Imf::FloatAttribute(meta.exposure));
    // Which layers are light groups, in order (a compositor rebuilding the beauty sums them).
    if (!meta.light_groups.empty()) header.insert("voxlux/lightGroups", Imf::StringVectorAttribute(meta.light_groups));
    if (const auto& c = meta.chromaticities) {
        auto xy = [](glm::vec2 v) { return Imath::V2f(v.x, v.y); };
        Imf::addChromaticities(header, Imf::Chromaticities(xy((*c)[0]), xy((*c)[1]), xy((*c)[2]), xy((*c)[3])));
    }
    return header;
}

// The names of knownCompressions(). DWA is lossy only for channels OpenEXR classifies as colour
// (R, G, B, Y with any layer prefix); it keeps A, depth.Z and the rest lossless.
Imf::Compression exrCompression(const std::string& name) {
    static const std::map<std::string, Imf::Compression> compressions{
        {"none", Imf::NO_COMPRESSION}, {"zip", Imf::ZIP_COMPRESSION},   {"zips", Imf::ZIPS_COMPRESSION},
        {"piz", Imf::PIZ_COMPRESSION}, {"dwaa", Imf::DWAA_COMPRESSION}, {"dwab", Imf::DWAB_COMPRESSION},
        {"rle", Imf::RLE_COMPRESSION}};
    auto found = compressions.find(name);
    if (found == compressions.end()) throw std::invalid_argument("unknown EXR compression '" + name + "'");
    return found->second;
}

float exrStorable(float v, bool half, ExrWriteReport& report) {
    constexpr float kHalfMax = 65504.0f;
    if (!std::isfinite(v)) {
        ++report.non_finite;
        return 0.0f;
    }
    if (half && std::abs(v) > kHalfMax) {
        ++report.half_overflow;
        return std::copysign(kHalfMax, v);
    }
    return v;
}

}  // namespace voxlux
