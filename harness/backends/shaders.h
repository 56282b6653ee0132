// GLSL sources: embedded at build time, overridable from a folder for development.
#pragma once
#include <string>
#include <vector>

namespace pxh {

struct EmbeddedShader {
    const char* path;  // relative to the source tree, e.g. "methods/pom/pom.frag.glsl"
    const char* source;
};

const std::vector<EmbeddedShader>& embedded_shaders();

// A shader's text and where it came from: "builtin" (the copy embedded at build time) or the
// file read.
struct ShaderSource {
    std::string text;
    std::string origin;
};

// The source of `path`: from override_dir (as DIR/path or DIR/basename) when that file
// exists, else the embedded copy. Throws std::runtime_error naming the path when neither has it.
// The caller checks that override_dir itself exists (a missing folder is an input error).
// builtin_text: the built-in copy when the caller has it (a method registered outside pxh,
// MethodInfo::shader_text) instead of the embedded table.
ShaderSource shader_source(const std::string& path, const std::string& override_dir,
                           const char* builtin_text = nullptr);
// Generated declarations in a shader (MethodInfo::shader_declarations): the shader has a line
// that starts with kDeclarationsLine, and the program is compiled with the generated text in its
// place. with_declarations returns that text and sets `line` to the line's number; it throws
// std::runtime_error naming `path` when the shader has no such line.
inline constexpr const char* kDeclarationsLine = "// @pxh-declarations";
std::string with_declarations(const std::string& text, const std::string& declarations,
                              const std::string& path, long& line);
// A shader file read as it is (a plug-in's): origin = its path; std::runtime_error naming it
// when it cannot be read.
ShaderSource shader_file_source(const std::string& path);

}  // namespace pxh
