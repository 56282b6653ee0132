// The GLSL backend: each method's fragment shader rendered offscreen (a GL context from
// harness/gl: OSMesa by default, or EGL) over an N x N RGBA32F framebuffer, read back and scored
// by the same metrics as the CPU reference.
#pragma once
#include <cstdint>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "harness/backends/backend.h"
#include "harness/backends/resource_textures.h"
#include "harness/backends/shader_interface.h"
#include "harness/scene/texture_levels.h"
#include "harness/scene/view.h"

namespace pxh {

class GlContext;

// The GLSL backend's timing: wall ms/frame, and the timer queries' frame time as the counter
// gpu_ms_per_frame (results.csv's gpu_ms_per_frame, _min, _max).
inline constexpr const char* kGpuTimeCounter = "gpu_ms_per_frame";
const TimingSpec& glsl_timing();

// What a GLSL program is compiled from, as plain data (it crosses to the GL child process,
// harness/backends/gl_worker.h): the method's name (the program cache's key), its shader.
struct GlslMethod {
    std::string name;
    std::string shader_file;  // MethodInfo::shader_file(): the built-in's embedded path
    bool has_builtin_text = false;
    std::string builtin_text;  // MethodInfo::shader_text (a method registered outside pxh)
    std::string declarations;  // MethodInfo::shader_declarations
    std::string plugin_shader, plugin_source, plugin_display;  // a plug-in's (MethodInfo)
    std::vector<std::string> plugin_files;  // its other files: includes, pxh's engine adapter
    std::string plugin_original, plugin_original_display;  // an HLSL/WGSL file's (MethodInfo)
    std::vector<ResourceSpec> resources;  // name, format, filter, wrap (not built here)
    static GlslMethod of(const MethodInfo& m);
};

// One row's draw: the program, its uniforms, and what it draws with (pointers to the caller's
// data, which must outlive the call).
// The depth a draw writes (methods/depth.h, docs/conventions.md section 11): main() writes
// gl_FragDepth = 0.5 + depth(X_w) / span into a 32-bit float depth target, read back as
// MethodOutput::depth. mode: 0 base, 1 hit, 2 engine; hit: 0 surface, 1 ray, 2 shader.
struct GlslDepth {
    int mode = 0, hit = 0;
    Vec3d axis{0, 0, -1};  // the view's depth axis f
    double span = 4;       // written depths beyond +-span / 2 are clamped by the target
};
// The depth settings of a method setting on a view; span = 4 (1 + s / min V.z), which holds
// every hit on the search lines of the slab and the offsets of the single-step methods.
GlslDepth glsl_depth_of(const MethodSpec& m, const View& rays, double scale);

struct GlslDraw {
    GlslMethod method;
    GlUniforms uniforms;  // method_uniforms(method, params)
    Scene<double> scene{};
    const HeightField* hf = nullptr;
    int samples = 0;
    std::string texture_format = "r32f";
    const LightSpec* light = nullptr;
    int frames = -1;  // < 0: the configured number of timed frames; 0: once, untimed
    const MethodResources* resources = nullptr;
    const std::vector<Vec3d>* V = nullptr;  // nullptr: every sample looks along scene.V
    // nullptr: the N x N sample grid (P from the fragment); else N x N points, sample j N + i
    // drawn at pixel (i, j), j = 0 the bottom row (a perspective view).
    const std::vector<Vec2d>* P = nullptr;
    // nullptr or empty: every sample inside; else 1 per inside sample (outside ones masked).
    const std::vector<uint8_t>* inside = nullptr;
    LodMode lod = LodMode::base;
    // The field's levels (levels[0] = *hf), uploaded as the height texture's mip chain; needed
    // when lod is not base, ignored when it is.
    const TextureLevels* levels = nullptr;
    // Each sample's lambda (pxh_lod(), and where lod = level fetches); nullptr: computed from J.
    const std::vector<double>* lambda = nullptr;
    // The footprints: one shared or one per sample; nullptr or empty: the N x N grid's.
    const std::vector<Footprint>* J = nullptr;
    GlslDepth depth{};
    // A curved base's per-sample depth axes (View::axes); nullptr: depth.axis for every sample.
    const std::vector<Vec3d>* axes = nullptr;
    // [shading]: the albedo's levels and the light; with them (and `levels`, `lambda`) the
    // draw also shades its uv with the GLSL twin of the shading (MethodOutput::shaded).
    const AlbedoLevels* albedo = nullptr;
    Vec3d light_dir{0, 0, 1};
};
// The draw of one method setting on one view (the Backend interface's arguments).
GlslDraw glsl_draw_of(const MethodSpec& m, const ViewInput& view, const Variant& v);

// A program that does not compile or link: the driver's log, one line per message, its
// locations mapped back to the files (FILE:LINE:COL: ...).
class GlslProgramError : public std::runtime_error {
  public:
    GlslProgramError(const std::string& what, std::vector<std::string> lines);
    std::vector<std::string> lines;
};

// "builtin", or the shader file(s) the method's program is (or would be) compiled from.
std::string glsl_shader_description(const GlslMethod& m, const std::string& shader_dir);

struct GlslOptions {
    std::string shader_dir;  // overrides the embedded shaders when non-empty
    int frames = 5;          // timed frames (median), after one warm-up frame
    std::vector<std::string> texture_formats{"r32f"};  // the variants, in row order
    std::string gl = "osmesa";  // the GL context (harness/gl/registry.cpp: osmesa, egl)
};

// A program kind as GlslBackend::check takes it: one byte, bit 0 the point map (any view but
// the orthographic grid), the lod mode above it.
inline uint8_t glsl_program_kind(bool point_map, LodMode lod) {
    return uint8_t((point_map ? 1 : 0) | (int(lod) << 1));
}

class GlslBackend : public Backend {
  public:
    // Creates the context and loads GL; throws std::runtime_error with a one-line reason.
    explicit GlslBackend(GlslOptions opt);
    ~GlslBackend();
    std::string renderer() const { return renderer_; }
    // The context: its name, GL_VENDOR, the driver behind it (run.json), and the bits of its
    // GL_TIME_ELAPSED counter (0: no GPU times, the gpu_ms columns stay empty).
    std::string context_name() const;
    std::string vendor() const { return vendor_; }
    std::map<std::string, std::string> driver() const;
    int timer_bits() const { return timer_bits_; }
    // Every shader source compiled so far: "builtin:PATH" or the file read -> sha256.
    const std::map<std::string, std::string>& compiled_sources() const { return compiled_sources_; }
    std::string version() const { return version_; }

    // The Backend interface: one variant per texture format, timed frames when the view is.
    std::string name() const override { return "glsl"; }
    std::vector<Variant> variants() const override;
    MethodOutput run(const MethodSpec& m, const ViewInput& view, const Variant& v) override;
    std::string shader_of(const MethodInfo& m) const override { return shader_description(m); }
    std::map<std::string, std::string> facts() const override;
    std::map<std::string, std::string> sources() const override { return compiled_sources_; }

    // Renders the method; throws std::runtime_error (shader compile/link log included) when
    // the method cannot run. texture_format: "r32f" | "r16" | "r8".
    // frames < 0: the configured number of timed frames; 0: render once, untimed.
    // V: nullptr (every sample looks along scene.V) or N x N directions, row-major like the
    // samples; the shader's pxh_V is then sample k's.
    MethodOutput run(const MethodSpec& m, const Scene<double>& scene, const HeightField& hf,
                     int samples, const std::string& texture_format, const LightSpec* light,
                     int frames = -1, const MethodResources* resources = nullptr,
                     const std::vector<Vec3d>* V = nullptr);
    // The same from plain data (what the GL child process runs).
    MethodOutput draw(const GlslDraw& d);
    // Compiles and links the method's program and checks its interface against `uniforms`
    // (and its resources' samplers): one line per problem ("FILE:LINE:COL: ..." for the
    // driver's messages), empty when it is ready to draw. `kinds`: every program the rows will
    // compile (glsl_program_kind: a perspective view's point map, the lod mode), each checked;
    // none: the orthographic grid at level 0.
    std::vector<std::string> check(const GlslMethod& m, const GlUniforms& uniforms,
                                   const std::vector<uint8_t>& kinds = {});
    // The height texture's level L as the last draw uploaded it (glGetTexImage, as float), and
    // its GL_TEXTURE_MAX_LEVEL: what a test checks the upload against.
    std::vector<float> height_texture_level(int level, int& width, int& height);
    int height_texture_max_level();

  private:
    struct Program {
        unsigned id = 0;
        std::string shader;  // "builtin", or the file(s) read from the shader folder
        std::string sha256;  // of the method's own source (not common.glsl)
        std::string what;    // "method 'NAME' (its shader files)", for messages
        std::map<std::string, ActiveUniform> active;  // the linked program's uniforms
        bool lod_map = false;                         // reads each sample's lambda (PXH_LOD_MAP)
    };
    // What a program is compiled for besides the method: common.glsl's PXH_* defines.
    struct ProgramKind {
        bool point_map = false;  // P and the inside flag per sample (not the grid)
        LodMode lod = LodMode::base;
    };
    const Program& program_for(const GlslMethod& m, ProgramKind kind);
    std::vector<std::string> check_program(const GlslMethod& m, const GlUniforms& uniforms,
                                           ProgramKind kind);

  public:
    // "builtin", or the shader file(s) the method's program is (or would be) compiled from.
    std::string shader_description(const MethodInfo& m) const {
        return glsl_shader_description(GlslMethod::of(m), opt_.shader_dir);
    }

  private:
    void upload(const HeightField& hf, const std::string& format, const TextureLevels* levels);
    void upload_sample_maps(const GlslDraw& d, const Program& program);
    void upload_view_map(const std::vector<Vec3d>& V, int samples);
    void ensure_framebuffer(int n);
    void set_uniforms(const Program& program, const GlslDraw& d);
    void draw_frames(int frames, MethodOutput& out);
    // Returns the second target's texels (shadow factors in x, y; the written depth in z).
    std::vector<float> read_back(int samples, bool light, const std::vector<uint8_t>* inside,
                                 MethodOutput& out);
    void read_depth(int samples, double span, const std::vector<float>& written, MethodOutput& out);
    void shade(const GlslDraw& d, MethodOutput& out);

    GlslOptions opt_;
    std::unique_ptr<GlContext> ctx_;
    std::string renderer_, version_, vendor_;
    int timer_bits_ = 0;
    unsigned vao_ = 0, fbo_ = 0, color_[2] = {0, 0}, depth_ = 0, texture_ = 0, view_map_ = 0;
    unsigned point_map_ = 0, lod_map_ = 0, grad_map_ = 0, axis_map_ = 0;
    int fb_size_ = 0;
    std::map<std::string, Program> programs_;
    std::map<std::string, std::string> compiled_sources_;
    ResourceTextures resource_textures_;
};

}  // namespace pxh
