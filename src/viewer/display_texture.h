// An RGBA8 GL texture of display texels for Dear ImGui to draw: linear filtering, clamped at the
// edges (a lat-long thumbnail's top and bottom rows must not bleed into each other). The same size
// again updates the texels in place; a new size allocates new storage. Needs the viewer's GL
// context, current at every call and alive when it is destroyed.
#pragma once
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace voxlux {

class DisplayTexture {
public:
    DisplayTexture() = default;
    ~DisplayTexture();
    DisplayTexture(const DisplayTexture&) = delete;
    DisplayTexture& operator=(const DisplayTexture&) = delete;

    void upload(int width, int height, const std::vector<uint8_t>& texels);
    // For ImGui::Image and AddImage; 0 before the first upload.
    void* imguiId() const { return reinterpret_cast<void*>(uintptr_t(id_)); }

private:
    unsigned id_ = 0;
    glm::ivec2 size_{0};
};

}  // namespace voxlux
