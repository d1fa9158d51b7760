#include "gl/gl_context.h"

#include <algorithm>
#include <cstdio>
#include <functional>
#include <memory>
#include <stdexcept>
#include <vector>

#include <epoxy/egl.h>
#include <epoxy/gl.h>

namespace voxlux {
namespace {

std::string eglError(const char* call) {
    char code[16];
    std::snprintf(code, sizeof code, "0x%04x", unsigned(eglGetError()));
    return std::string(call) + " failed (EGL error " + code + ")";
}

// A display worth trying, opened only when its turn comes, and how messages name it.
struct Candidate {
    std::string what;
    std::function<EGLDisplay()> display;  // EGL_NO_DISPLAY when the platform is unavailable
};

EGLDisplay platformDisplay(EGLenum platform, void* native) {
    // eglGetPlatformDisplayEXT itself needs the EGL_EXT_platform_base client extension.
    return epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_EXT_platform_base")
               ? eglGetPlatformDisplayEXT(platform, native, nullptr)
               : EGL_NO_DISPLAY;
}

// The EGL devices, GPUs first: Mesa enumerates its CPU rasteriser as a device too, ahead of them.
std::vector<EGLDeviceEXT> devices() {
    if (!epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_EXT_platform_device") ||
        !epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_EXT_device_enumeration"))
        return {};
    EGLint count = 0;
    if (!eglQueryDevicesEXT(0, nullptr, &count) || count <= 0) return {};
    std::vector<EGLDeviceEXT> out(count);
    if (!eglQueryDevicesEXT(count, out.data(), &count)) return {};
    out.resize(count);
    std::stable_partition(out.begin(), out.end(), [](EGLDeviceEXT d) {
        return !epoxy_extension_in_string(eglQueryDeviceStringEXT(d, EGL_EXTENSIONS), "EGL_MESA_device_software");
    });
    return out;
}

// In order: the device platform (how NVIDIA runs headless), Mesa's surfaceless platform, the
// default display. Every platform is listed, even when unavailable, so a failure names them all.
std::vector<Candidate> candidates() {
    std::vector<Candidate> out;
    const std::vector<EGLDeviceEXT> found = devices();
    for (size_t i = 0; i < found.size(); ++i)
        out.push_back({"EGL device " + std::to_string(i),
                       [d = found[i]] { return platformDisplay(EGL_PLATFORM_DEVICE_EXT, d); }});
    if (found.empty()) out.push_back({"EGL devices", [] { return EGL_NO_DISPLAY; }});
    out.push_back({"Mesa surfaceless platform", [] {
                       return epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_MESA_platform_surfaceless")
                                  ? platformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY)
                                  : EGL_NO_DISPLAY;
                   }});
    out.push_back({"default display", [] { return eglGetDisplay(EGL_DEFAULT_DISPLAY); }});
    return out;
}

bool isSoftwareRenderer(const std::string& r) {
    return r.find("llvmpipe") != std::string::npos || r.find("softpipe") != std::string::npos ||
           r.find("SWR") != std::string::npos;
}

class Context {
public:
    Context() {
        std::string reasons;
        for (const Candidate& c : candidates()) {
            const EGLDisplay d = c.display();
            std::string why = d == EGL_NO_DISPLAY ? "unavailable" : open(d);
            if (why.empty()) {
                info_.display = c.what;
                break;
            }
            reasons += (reasons.empty() ? "" : "; ") + c.what + ": " + why;
        }
        if (context_ == EGL_NO_CONTEXT)
            throw std::runtime_error("cannot create a headless OpenGL 4.5 core context through EGL (" + reasons + ")");
        const char* renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
        info_.renderer = renderer ? renderer : "unknown renderer";
        info_.software = isSoftwareRenderer(info_.renderer);
    }

    ~Context() {
        eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        eglDestroyContext(display_, context_);
        eglTerminate(display_);
    }

    Context(const Context&) = delete;
    Context& operator=(const Context&) = delete;

    // Current-ness is per thread and per client API, so bind the API before asking.
    void makeCurrent() const {
        eglBindAPI(EGL_OPENGL_API);
        if (eglGetCurrentContext() != context_ &&
            !eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_))
            throw std::runtime_error("cannot make the OpenGL context current: " + eglError("eglMakeCurrent"));
    }

    const GlContextInfo& info() const { return info_; }

private:
    // Makes a current surfaceless 4.5 core context on `d`; returns why not, or "" on success.
    std::string open(EGLDisplay d) {
        EGLint major = 0, minor = 0;
        if (!eglInitialize(d, &major, &minor)) return eglError("eglInitialize");
        std::string why = createOn(d);
        if (!why.empty()) eglTerminate(d);
        return why;
    }

    std::string createOn(EGLDisplay d) {
        if (!epoxy_has_egl_extension(d, "EGL_KHR_surfaceless_context")) return "no EGL_KHR_surfaceless_context";
        if (!eglBindAPI(EGL_OPENGL_API)) return eglError("eglBindAPI(EGL_OPENGL_API)");
        const EGLint config_attribs[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT,
                                         EGL_NONE};
        EGLConfig config = nullptr;
        EGLint configs = 0;
        if (!eglChooseConfig(d, config_attribs, &config, 1, &configs)) return eglError("eglChooseConfig");
        if (configs == 0) return "no EGL config renders desktop OpenGL";
        const EGLint context_attribs[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 5,
                                          EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                          EGL_NONE};
        EGLContext ctx = eglCreateContext(d, config, EGL_NO_CONTEXT, context_attribs);
        if (ctx == EGL_NO_CONTEXT) return eglError("eglCreateContext(OpenGL 4.5 core)");
        if (!eglMakeCurrent(d, EGL_NO_SURFACE, EGL_NO_SURFACE, ctx)) {
            std::string why = eglError("eglMakeCurrent(surfaceless)");
            eglDestroyContext(d, ctx);
            return why;
        }
        display_ = d;
        context_ = ctx;
        return "";
    }

    EGLDisplay display_ = EGL_NO_DISPLAY;
    EGLContext context_ = EGL_NO_CONTEXT;
    GlContextInfo info_;
};

}  // namespace

const GlContextInfo& ensureGlContext() {
    struct Holder {
        std::unique_ptr<Context> context;
        std::string error;
    };
    static Holder holder = [] {
        Holder h;
        try {
            h.context = std::make_unique<Context>();
        } catch (const std::exception& e) {
            h.error = e.what();
        }
        return h;
    }();
    if (!holder.context) throw std::runtime_error(holder.error);
    holder.context->makeCurrent();
    return holder.context->info();
}

}  // namespace voxlux
