// Renders the cloud given on the command line at 32x24 through an installed voxlux and prints
// the covered pixels; exits 1 when nothing was rendered.
#include <cstdio>

#include "render/renderer.h"

int main(int argc, char** argv) {
    if (argc != 2) return 2;
    voxlux::Scene scene;
    scene.volume().path = argv[1];
    scene.volume().material.density_scale = 40.0f;
    scene.render.width = 32;
    scene.render.height = 24;
    scene.render.backend = voxlux::Backend::Cpu;
    scene.lights = {voxlux::Light{}};
    voxlux::Renderer renderer(scene);
    const voxlux::FrameResult frame = renderer.render(std::nullopt, false);
    int covered = 0;
    for (const auto& px : frame.image.pixels) covered += px.rgba.w > 0.01f;
    std::printf("rendered %dx%d through find_package(voxlux): %d pixels covered\n", frame.image.width, frame.image.height, covered);
    return covered > 0 ? 0 : 1;
}
