// The EGL context: headless, no window system. Displays are tried in this order:
//   1. a hardware device (EGL_EXT_platform_device, devices without EGL_MESA_device_software):
//      what a GPU takes with its vendor's libEGL on a headless machine (NVIDIA: libEGL_nvidia);
//   2. Mesa's surfaceless platform (EGL_MESA_platform_surfaceless): llvmpipe where no GPU is;
//   3. a software device, then 4. eglGetDisplay(EGL_DEFAULT_DISPLAY).
// Hardware first: on a GPU machine Mesa's surfaceless platform (installed by run.sh) would
// otherwise win and render in software. The first display that gives an OpenGL 4.5 core
// context, current without a surface (EGL_KHR_surfaceless_context), is kept.
#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <cstdio>
#include <functional>
#include <stdexcept>

#include "harness/gl/context.h"

namespace pxh {
namespace {

std::string hex(EGLint code) {
    char buf[16];
    std::snprintf(buf, sizeof buf, "0x%04x", unsigned(code));
    return buf;
}

bool has_extension(const char* list, const std::string& ext) {
    if (!list) return false;
    const std::string s = std::string(" ") + list + " ";
    return s.find(" " + ext + " ") != std::string::npos;
}

std::string str(const char* s) {  // trimmed (Mesa ends some lists with a space)
    std::string t = s ? s : "";
    while (!t.empty() && t.back() == ' ') t.pop_back();
    return t;
}

// A display to try: how to get it, and what run.json calls it.
struct Candidate {
    std::string platform;  // "device 0", "surfaceless", "device 1 (software)", "default"
    std::string device_extensions, device_file;
    std::function<EGLDisplay()> get;
};

class EglContext final : public GlContext {
  public:
    EglContext() {
        std::string failures;
        for (const Candidate& c : candidates()) {
            const std::string err = try_display(c);
            if (err.empty()) {
                driver_ = {{"platform", c.platform},
                           {"EGL_VENDOR", str(eglQueryString(dpy_, EGL_VENDOR))},
                           {"EGL_VERSION", str(eglQueryString(dpy_, EGL_VERSION))},
                           {"EGL_CLIENT_APIS", str(eglQueryString(dpy_, EGL_CLIENT_APIS))}};
                if (!c.device_extensions.empty())
                    driver_["device_extensions"] = c.device_extensions;
                if (!c.device_file.empty()) driver_["device_file"] = c.device_file;
                return;
            }
            failures += (failures.empty() ? "" : "; ") + c.platform + ": " + err;
        }
        throw std::runtime_error("EGL: no OpenGL 4.5 core context (" +
                                 (failures.empty() ? std::string("no display to try") : failures) +
                                 "; is libegl-mesa0 or the GPU vendor's libEGL installed?)");
    }
    // The display stays initialised: EGL has one display per platform and native display, so
    // eglTerminate would also end every other context on it.
    ~EglContext() override {
        if (eglGetCurrentContext() == ctx_)
            eglMakeCurrent(dpy_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        eglDestroyContext(dpy_, ctx_);
    }
    EglContext(const EglContext&) = delete;
    EglContext& operator=(const EglContext&) = delete;

    void make_current() override {
        if (!eglBindAPI(EGL_OPENGL_API) ||
            !eglMakeCurrent(dpy_, EGL_NO_SURFACE, EGL_NO_SURFACE, ctx_))
            throw std::runtime_error("EGL: eglMakeCurrent failed (error " + hex(eglGetError()) +
                                     ")");
    }
    GlProc proc_address(const char* name) const override {
        return reinterpret_cast<GlProc>(eglGetProcAddress(name));
    }
    std::string name() const override { return "egl"; }
    std::map<std::string, std::string> driver() const override { return driver_; }

  private:
    static std::vector<Candidate> candidates();
    std::string try_display(const Candidate& c);

    EGLDisplay dpy_ = EGL_NO_DISPLAY;
    EGLContext ctx_ = EGL_NO_CONTEXT;
    std::map<std::string, std::string> driver_;
};

std::vector<Candidate> EglContext::candidates() {
    // Client extensions (EGL 1.5 or EGL_EXT_client_extensions); null without them.
    const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (!client) eglGetError();  // clear EGL_BAD_DISPLAY
    auto get_platform_display = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
        eglGetProcAddress("eglGetPlatformDisplayEXT"));
    std::vector<Candidate> hardware, software, out;
    if (get_platform_display && has_extension(client, "EGL_EXT_platform_device") &&
        has_extension(client, "EGL_EXT_device_enumeration")) {
        auto query_devices =
            reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
        auto query_string = reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(
            eglGetProcAddress("eglQueryDeviceStringEXT"));
        EGLDeviceEXT devices[16];
        EGLint n = 0;
        if (query_devices && query_string && query_devices(16, devices, &n)) {
            for (EGLint i = 0; i < n; ++i) {
                Candidate c;
                c.device_extensions = str(query_string(devices[i], EGL_EXTENSIONS));
                if (has_extension(c.device_extensions.c_str(), "EGL_EXT_device_drm"))
                    c.device_file = str(query_string(devices[i], EGL_DRM_DEVICE_FILE_EXT));
                const bool soft =
                    has_extension(c.device_extensions.c_str(), "EGL_MESA_device_software");
                c.platform = "device " + std::to_string(i) + (soft ? " (software)" : "");
                const EGLDeviceEXT dev = devices[i];
                c.get = [get_platform_display, dev] {
                    return get_platform_display(EGL_PLATFORM_DEVICE_EXT, dev, nullptr);
                };
                (soft ? software : hardware).push_back(std::move(c));
            }
        }
        eglGetError();  // a failed enumeration is not this context's error
    }
    out = std::move(hardware);
    if (get_platform_display && has_extension(client, "EGL_MESA_platform_surfaceless"))
        out.push_back({"surfaceless", "", "", [get_platform_display] {
                           return get_platform_display(EGL_PLATFORM_SURFACELESS_MESA,
                                                       EGL_DEFAULT_DISPLAY, nullptr);
                       }});
    for (auto& c : software) out.push_back(std::move(c));
    out.push_back({"default", "", "", [] { return eglGetDisplay(EGL_DEFAULT_DISPLAY); }});
    return out;
}

// "" when `c` gave a current 4.5 core context (kept in dpy_, ctx_), else what failed.
std::string EglContext::try_display(const Candidate& c) {
    const EGLDisplay dpy = c.get();
    if (dpy == EGL_NO_DISPLAY)
        return "eglGetPlatformDisplay failed (error " + hex(eglGetError()) + ")";
    EGLint major = 0, minor = 0;
    if (!eglInitialize(dpy, &major, &minor))
        return "eglInitialize failed (error " + hex(eglGetError()) + ")";
    const char* ext = eglQueryString(dpy, EGL_EXTENSIONS);
    const bool egl15 = major > 1 || (major == 1 && minor >= 5);
    if (!egl15 && !has_extension(ext, "EGL_KHR_create_context"))
        return "no EGL_KHR_create_context (EGL " + std::to_string(major) + "." +
               std::to_string(minor) + ")";
    if (!has_extension(ext, "EGL_KHR_surfaceless_context")) return "no EGL_KHR_surfaceless_context";
    if (!eglBindAPI(EGL_OPENGL_API))
        return "eglBindAPI(EGL_OPENGL_API) failed (error " + hex(eglGetError()) + ")";
    // No config needed when the display allows it; else any config that can render OpenGL.
    EGLConfig config = EGL_NO_CONFIG_KHR;
    if (!has_extension(ext, "EGL_KHR_no_config_context")) {
        const EGLint want[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE, 0, EGL_NONE};
        EGLint n = 0;
        if (!eglChooseConfig(dpy, want, &config, 1, &n) || n < 1)
            return "eglChooseConfig found no OpenGL config (error " + hex(eglGetError()) + ")";
    }
    const EGLint attribs[] = {EGL_CONTEXT_MAJOR_VERSION_KHR,
                              4,
                              EGL_CONTEXT_MINOR_VERSION_KHR,
                              5,
                              EGL_CONTEXT_OPENGL_PROFILE_MASK_KHR,
                              EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT_KHR,
                              EGL_NONE};
    const EGLContext ctx = eglCreateContext(dpy, config, EGL_NO_CONTEXT, attribs);
    if (ctx == EGL_NO_CONTEXT)
        return "eglCreateContext(OpenGL 4.5 core) failed (error " + hex(eglGetError()) + ")";
    if (!eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, ctx)) {
        const EGLint err = eglGetError();
        eglDestroyContext(dpy, ctx);
        return "eglMakeCurrent(EGL_NO_SURFACE) failed (error " + hex(err) + ")";
    }
    dpy_ = dpy;
    ctx_ = ctx;
    return "";
}

}  // namespace

std::unique_ptr<GlContext> make_egl_context() { return std::make_unique<EglContext>(); }

}  // namespace pxh
