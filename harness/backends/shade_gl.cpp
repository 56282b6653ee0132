#include "harness/backends/shade_gl.h"

#include <glad/gl.h>

#include <cmath>
#include <stdexcept>
#include <string>

namespace pxh {

namespace {

const char* kVertex = R"(#version 450 core
void main() {
    vec2 p = vec2(gl_VertexID == 1 ? 3.0 : -1.0, gl_VertexID == 2 ? 3.0 : -1.0);
    gl_Position = vec4(p, 0.0, 1.0);
}
)";

// harness/scene/shading.cpp, line for line: height_gradient, shade_linear, srgb_encode.
const char* kFragment = R"(#version 450 core
uniform sampler2D u_height;  // the field's levels 0..q
uniform sampler2D u_albedo;  // the albedo's levels (linear RGB)
uniform sampler2D u_pixel;   // per pixel: u, v, lambda, covered
uniform int u_last;          // q
uniform float u_scale;       // s
uniform vec3 u_light;
uniform float u_albedo_lod;
uniform int u_albedo_last;   // the albedo's last level
uniform ivec2 u_height_size, u_albedo_size;  // level 0's texels
out vec4 o_color;

// Section 1's bilinear rule on one level, texel by texel (texelFetch, repeat wrapping): the
// CPU twin's bilinear_texels, not the driver's filtering.
ivec2 wrapped(ivec2 ij, ivec2 size) {
    vec2 f = vec2(ij), s = vec2(size);
    return ivec2(f - s * floor(f / s));
}
// A level's size from level 0's (GL's rule, max(1, n0 >> L)): textureSize with a level that
// differs between the pixels of a SIMD group gave some of them another level's size on
// llvmpipe.
ivec2 level_size(ivec2 size0, int level) { return max(ivec2(1), size0 >> level); }
vec4 bilinear(sampler2D t, ivec2 size0, int level, vec2 uv) {
    ivec2 size = level_size(size0, level);
    vec2 x = uv * vec2(size) - 0.5;
    vec2 f0 = floor(x);
    vec2 f = x - f0;
    ivec2 i0 = wrapped(ivec2(f0), size);
    ivec2 i1 = wrapped(i0 + ivec2(1, 1), size);
    vec4 h00 = texelFetch(t, i0, level), h10 = texelFetch(t, ivec2(i1.x, i0.y), level);
    vec4 h01 = texelFetch(t, ivec2(i0.x, i1.y), level), h11 = texelFetch(t, i1, level);
    vec4 a = h00 + (h10 - h00) * f.x;
    vec4 b = h01 + (h11 - h01) * f.x;
    return a + (b - a) * f.y;
}
// level_fetch's rule without branches (llvmpipe gave wrong texels to some pixels of a SIMD
// group whose pixels took different branches): lambda clamped to [0, last], the two levels
// floor(l) and the next (the last twice at the end), blended by l - floor(l); at l = 0 or
// l = last the blend's weight is 0 and the value the first level's, as level_fetch's.
vec4 trilinear(sampler2D t, ivec2 size0, int last, vec2 uv, float lambda) {
    float l = clamp(lambda, 0.0, float(last));
    float d1f = floor(l);
    int d1 = int(d1f);
    vec4 b1 = bilinear(t, size0, d1, uv), b2 = bilinear(t, size0, min(d1 + 1, last), uv);
    return b1 + (b2 - b1) * (l - d1f);
}

vec2 level_gradient(vec2 uv, int level) {
    vec2 d = 1.0 / vec2(level_size(u_height_size, level));
    float hu1 = bilinear(u_height, u_height_size, level, uv + vec2(d.x, 0.0)).r;
    float hu0 = bilinear(u_height, u_height_size, level, uv - vec2(d.x, 0.0)).r;
    float hv1 = bilinear(u_height, u_height_size, level, uv + vec2(0.0, d.y)).r;
    float hv0 = bilinear(u_height, u_height_size, level, uv - vec2(0.0, d.y)).r;
    return vec2((hu1 - hu0) / (2.0 * d.x), (hv1 - hv0) / (2.0 * d.y));
}

vec2 height_gradient(vec2 uv, float lambda) {
    float l = clamp(lambda, 0.0, float(u_last));
    float d1f = floor(l);
    int d1 = int(d1f);
    vec2 g1 = level_gradient(uv, d1), g2 = level_gradient(uv, min(d1 + 1, u_last));
    return g1 + (g2 - g1) * (l - d1f);
}

float srgb_encode(float c) {
    c = clamp(c, 0.0, 1.0);
    return c <= 0.0031308 ? 12.92 * c : 1.055 * pow(c, 1.0 / 2.4) - 0.055;
}

// No early return for the background either: every pixel of a SIMD group takes one path.
void main() {
    vec4 p = texelFetch(u_pixel, ivec2(gl_FragCoord.xy), 0);
    vec2 g = height_gradient(p.xy, p.z);
    float nx = -u_scale * g.x, ny = -u_scale * g.y;
    float ndotl = (nx * u_light.x + ny * u_light.y + u_light.z) / sqrt(nx * nx + ny * ny + 1.0);
    float light = 0.2 + 0.8 * max(0.0, ndotl);
    vec3 a = trilinear(u_albedo, u_albedo_size, u_albedo_last, p.xy, p.z + u_albedo_lod).rgb;
    vec3 c = a * light;
    vec4 shaded = vec4(srgb_encode(c.r), srgb_encode(c.g), srgb_encode(c.b), 1.0);
    o_color = p.w == 0.0 ? vec4(0.5, 0.5, 0.5, 1.0) : shaded;
}
)";

GLuint compile(GLenum type, const char* src) {
    const GLuint sh = glCreateShader(type);
    glShaderSource(sh, 1, &src, nullptr);
    glCompileShader(sh);
    GLint ok = 0;
    glGetShaderiv(sh, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[2048] = {};
        glGetShaderInfoLog(sh, sizeof log, nullptr, log);
        glDeleteShader(sh);
        throw std::runtime_error(std::string("the shading shader does not compile: ") + log);
    }
    return sh;
}

GLuint link_program() {
    const GLuint vs = compile(GL_VERTEX_SHADER, kVertex),
                 fs = compile(GL_FRAGMENT_SHADER, kFragment);
    const GLuint prog = glCreateProgram();
    glAttachShader(prog, vs);
    glAttachShader(prog, fs);
    glLinkProgram(prog);
    glDeleteShader(vs);
    glDeleteShader(fs);
    GLint ok = 0;
    glGetProgramiv(prog, GL_LINK_STATUS, &ok);
    if (!ok) {
        glDeleteProgram(prog);
        throw std::runtime_error("the shading program does not link");
    }
    return prog;
}

// A mip chain of `channels` float channels a texel, level L from fill(L, texels).
template <typename Fill>
GLuint mip_texture(int levels, int channels, Fill fill) {
    GLuint tex = 0;
    glGenTextures(1, &tex);
    glBindTexture(GL_TEXTURE_2D, tex);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    const GLenum internal = channels == 1 ? GL_R32F : GL_RGB32F;
    const GLenum format = channels == 1 ? GL_RED : GL_RGB;
    for (int l = 0; l < levels; ++l) {
        int w = 0, h = 0;
        const std::vector<float> texels = fill(l, w, h);
        glTexImage2D(GL_TEXTURE_2D, l, GLint(internal), w, h, 0, format, GL_FLOAT, texels.data());
    }
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_BASE_LEVEL, 0);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, levels - 1);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_REPEAT);
    return tex;
}

GLuint pixel_texture(const ShadeGlInput& in) {
    const size_t count = size_t(in.n) * size_t(in.n);
    std::vector<float> px(count * 4, 0.0f);
    for (size_t k = 0; k < count && k < in.uv.size(); ++k) {
        const Vec2d uv = in.uv[k];
        const bool covered =
            (k >= in.covered.size() || in.covered[k]) && std::isfinite(uv.x) && std::isfinite(uv.y);
        if (!covered) continue;
        const double lambda =
            k < in.lambda.size() && std::isfinite(in.lambda[k]) ? in.lambda[k] : 0;
        px[4 * k] = float(uv.x);
        px[4 * k + 1] = float(uv.y);
        px[4 * k + 2] = float(lambda);
        px[4 * k + 3] = 1.0f;
    }
    GLuint tex = 0;
    glGenTextures(1, &tex);
    glBindTexture(GL_TEXTURE_2D, tex);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, in.n, in.n, 0, GL_RGBA, GL_FLOAT, px.data());
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, 0);
    return tex;
}

}  // namespace

std::vector<float> shade_gl(GlContext& ctx, const ShadeGlInput& in) {
    use_gl_context(ctx);
    const Material& m = in.material;
    const TextureLevels& hl = *m.heights;
    const AlbedoLevels& al = *m.albedo;
    const GLuint prog = link_program();
    GLuint vao = 0, fbo = 0, target = 0;
    glGenVertexArrays(1, &vao);
    glBindVertexArray(vao);
    GLuint tex[3];
    glActiveTexture(GL_TEXTURE0);
    tex[0] = mip_texture(int(hl.levels.size()), 1, [&](int l, int& w, int& h) {
        const HeightField& f = hl.levels[size_t(l)];
        w = f.width;
        h = f.height;
        return f.texels;
    });
    glActiveTexture(GL_TEXTURE1);
    tex[1] = mip_texture(int(al.channel[0].levels.size()), 3, [&](int l, int& w, int& h) {
        const HeightField& r = al.channel[0].levels[size_t(l)];
        w = r.width;
        h = r.height;
        std::vector<float> rgb(r.texels.size() * 3);
        for (size_t k = 0; k < r.texels.size(); ++k)
            for (size_t c = 0; c < 3; ++c)
                rgb[3 * k + c] = al.channel[c].levels[size_t(l)].texels[k];
        return rgb;
    });
    glActiveTexture(GL_TEXTURE2);
    tex[2] = pixel_texture(in);
    glActiveTexture(GL_TEXTURE3);  // the target: not on the units the shader samples
    glGenTextures(1, &target);
    glBindTexture(GL_TEXTURE_2D, target);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, in.n, in.n, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
    glGenFramebuffers(1, &fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, target, 0);
    const bool complete = glCheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
    std::vector<uint8_t> bytes(size_t(in.n) * size_t(in.n) * 4);
    if (complete) {
        glViewport(0, 0, in.n, in.n);
        glUseProgram(prog);
        glUniform1i(glGetUniformLocation(prog, "u_height"), 0);
        glUniform1i(glGetUniformLocation(prog, "u_albedo"), 1);
        glUniform1i(glGetUniformLocation(prog, "u_pixel"), 2);
        glUniform1i(glGetUniformLocation(prog, "u_last"), hl.last());
        glUniform1f(glGetUniformLocation(prog, "u_scale"), float(m.scale));
        glUniform3f(glGetUniformLocation(prog, "u_light"), float(m.light.x), float(m.light.y),
                    float(m.light.z));
        glUniform1f(glGetUniformLocation(prog, "u_albedo_lod"), float(m.albedo_lod));
        glUniform1i(glGetUniformLocation(prog, "u_albedo_last"), al.channel[0].last());
        glUniform2i(glGetUniformLocation(prog, "u_height_size"), hl.levels[0].width,
                    hl.levels[0].height);
        glUniform2i(glGetUniformLocation(prog, "u_albedo_size"), al.width, al.height);
        glDrawArrays(GL_TRIANGLES, 0, 3);
        glPixelStorei(GL_PACK_ALIGNMENT, 1);
        glReadPixels(0, 0, in.n, in.n, GL_RGBA, GL_UNSIGNED_BYTE, bytes.data());
    }
    const GLenum err = glGetError();
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glDeleteFramebuffers(1, &fbo);
    glDeleteTextures(1, &target);
    glDeleteTextures(3, tex);
    glDeleteVertexArrays(1, &vao);
    glDeleteProgram(prog);
    if (!complete) throw std::runtime_error("the shading target is not complete");
    if (err != GL_NO_ERROR)
        throw std::runtime_error("GL error " + std::to_string(err) + " shading");
    std::vector<float> out(size_t(in.n) * size_t(in.n) * 3);
    for (size_t k = 0; k < out.size() / 3; ++k)
        for (size_t c = 0; c < 3; ++c) out[3 * k + c] = float(bytes[4 * k + c]) / 255.0f;
    return out;
}

}  // namespace pxh
