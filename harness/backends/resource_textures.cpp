#include "harness/backends/resource_textures.h"

#include <glad/gl.h>

#include <stdexcept>
#include <string>

namespace pxh {

void ResourceTextures::release() {
    if (!textures_.empty()) glDeleteTextures(GLsizei(textures_.size()), textures_.data());
    textures_.clear();
}

void ResourceTextures::bind(unsigned program, const MethodResources& res, int first_unit) {
    while (textures_.size() < res.items.size()) {
        GLuint t = 0;
        glGenTextures(1, &t);
        textures_.push_back(t);
    }
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    for (size_t k = 0; k < res.items.size(); ++k) {
        const ResourceSpec& spec = *res.items[k].spec;
        const ResourceImage& img = *res.items[k].image;
        const bool rgba = spec.format == TexelFormat::RGBA32F;
        const bool nearest = spec.filter == TexFilter::Nearest;
        const bool mips = img.levels.size() > 1;
        glActiveTexture(GLenum(GL_TEXTURE0 + first_unit + int(k)));
        glBindTexture(GL_TEXTURE_2D, textures_[k]);
        for (size_t L = 0; L < img.levels.size(); ++L) {
            const ResourceLevel& lv = img.levels[L];
            glTexImage2D(GL_TEXTURE_2D, GLint(L), rgba ? GL_RGBA32F : GL_R32F, lv.width, lv.height,
                         0, rgba ? GL_RGBA : GL_RED, GL_FLOAT, lv.texels.data());
        }
        // Integer levels only (pxh_texture): the nearest level, filtered within it.
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER,
                        mips ? (nearest ? GL_NEAREST_MIPMAP_NEAREST : GL_LINEAR_MIPMAP_NEAREST)
                             : (nearest ? GL_NEAREST : GL_LINEAR));
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, nearest ? GL_NEAREST : GL_LINEAR);
        const GLint wrap = spec.wrap == TexWrap::Repeat ? GL_REPEAT : GL_CLAMP_TO_EDGE;
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, wrap);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, wrap);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_BASE_LEVEL, 0);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, GLint(img.levels.size()) - 1);
        if (glGetError() != GL_NO_ERROR)
            throw std::runtime_error(
                "resource '" + spec.name + "': cannot upload " + std::to_string(img.levels.size()) +
                " level(s) of " + std::to_string(img.levels[0].width) + " x " +
                std::to_string(img.levels[0].height) + (rgba ? " rgba32f" : " r32f"));
        glUniform1i(glGetUniformLocation(program, spec.name.c_str()), first_unit + int(k));
    }
    glActiveTexture(GL_TEXTURE0);
}

}  // namespace pxh
