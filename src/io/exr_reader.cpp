#include "io/exr_reader.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <algorithm>
#include <exception>
#include <mutex>
#include <vector>

#include "core/error.h"

namespace voxlux {

// voxlux renders at most 16384 pixels a side (render.resolution). A larger data window in a file
// given to `study` is refused by OpenEXR's header check before anything is allocated for it.
constexpr int kMaxSide = 16384;

namespace {

void limitImageSize() {
    static std::once_flag limits;   // OpenEXR's limits are process-wide
    std::call_once(limits, [] {
        Imf::Header::setMaxImageSize(kMaxSide, kMaxSide);
        Imf::Header::setMaxTileSize(kMaxSide, kMaxSide);
    });
}

}  // namespace

RenderImage readExrRgba(const std::string& path) {
    try {
        limitImageSize();
        Imf::InputFile file(path.c_str());
        const Imath::Box2i window = file.header().dataWindow();
        RenderImage image;
        image.width = window.max.x - window.min.x + 1;
        image.height = window.max.y - window.min.y + 1;
        image.pixels.resize(size_t(image.width) * image.height);
        // Slices write straight into the pixels' rgba, offset so the data window starts at pixel 0.
        const size_t xstride = sizeof(kernel::VxPixel), ystride = xstride * image.width;
        char* origin = reinterpret_cast<char*>(image.pixels.data()) -
                       (ptrdiff_t(window.min.x) * ptrdiff_t(xstride) + ptrdiff_t(window.min.y) * ptrdiff_t(ystride));
        Imf::FrameBuffer fb;
        const char* names[] = {"R", "G", "B", "A"};
        for (int c = 0; c < 4; ++c)
            fb.insert(names[c], Imf::Slice(Imf::FLOAT, origin + offsetof(kernel::VxPixel, rgba) + c * sizeof(float),
                                           xstride, ystride, 1, 1, 0.0));
        file.setFrameBuffer(fb);
        file.readPixels(window.min.y, window.max.y);
        return image;
    } catch (const std::exception& e) {
        throw InputError(path + ": cannot read EXR (" + e.what() + ")");
    }
}

ExrChannel readExrChannel(const std::string& path, const std::string& name, float outside) {
    std::string channels;
    try {
        limitImageSize();
        Imf::InputFile file(path.c_str());
        if (!file.header().channels().findChannel(name)) {
            for (auto c = file.header().channels().begin(); c != file.header().channels().end(); ++c)
                channels += std::string(channels.empty() ? "" : ", ") + c.name();
        } else {
            // The data window's pixels, then those inside the display window at their place in it.
            const Imath::Box2i data = file.header().dataWindow(), display = file.header().displayWindow();
            const int64_t display_width = int64_t(display.max.x) - display.min.x + 1, display_height = int64_t(display.max.y) - display.min.y + 1;
            // OpenEXR bounds the data window (setMaxImageSize); the frame is bounded here, before
            // anything the size of it is allocated.
            if (display_width < 1 || display_height < 1 || display_width > kMaxSide || display_height > kMaxSide)
                throw InputError(path + ": its display window is " + std::to_string(display_width) + "x" + std::to_string(display_height) +
                                 " pixels (at most " + std::to_string(kMaxSide) + " a side)");
            const int data_width = data.max.x - data.min.x + 1, data_height = data.max.y - data.min.y + 1;
            std::vector<float> read(size_t(data_width) * data_height);
            char* origin = reinterpret_cast<char*>(read.data()) -
                           (ptrdiff_t(data.min.x) + ptrdiff_t(data.min.y) * ptrdiff_t(data_width)) * ptrdiff_t(sizeof(float));
            Imf::FrameBuffer fb;
            fb.insert(name, Imf::Slice(Imf::FLOAT, origin, sizeof(float), sizeof(float) * size_t(data_width)));
            file.setFrameBuffer(fb);
            file.readPixels(data.min.y, data.max.y);
            ExrChannel out;
            out.width = int(display_width);
            out.height = int(display_height);
            out.values.assign(size_t(out.width) * out.height, outside);
            for (int y = std::max(data.min.y, display.min.y); y <= std::min(data.max.y, display.max.y); ++y)
                for (int x = std::max(data.min.x, display.min.x); x <= std::min(data.max.x, display.max.x); ++x)
                    out.values[size_t(y - display.min.y) * out.width + size_t(x - display.min.x)] =
                        read[size_t(y - data.min.y) * data_width + size_t(x - data.min.x)];
            return out;
        }
    } catch (const InputError&) {
        throw;
    } catch (const std::exception& e) {
        throw InputError(path + ": cannot read EXR (" + e.what() + ")");
    }
    throw InputError(path + ": no channel '" + name + "' (it has " + (channels.empty() ? std::string("none") : channels) + ")");
}

}  // namespace voxlux
