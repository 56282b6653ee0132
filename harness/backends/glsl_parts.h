// Shared by the GLSL backend's files (glsl_backend.cpp and the glsl_*.cpp beside it): the
// driver's log mapped to the files compiled (glsl_compile.cpp) and the texture units.
#pragma once
#include <map>
#include <string>
#include <vector>

namespace pxh::glsl_detail {

constexpr long kBodyLine = 100000;  // the method's file starts at line kBodyLine + 1

// The method file's line of a line of the compiled method text: the generated declarations
// (`count` lines written in place of line `at`, shaders.h) are reported at that line.
struct BodyLines {
    long at = 0, count = 0;
    long file_line(long ln) const {
        if (count == 0 || ln < at) return ln;
        return ln < at + count ? at : ln - count + 1;
    }
};

// The raw log (several lines) of a shader or program.
std::string raw_log(unsigned object, bool program);

// The driver's messages, one per line, with Mesa's "S:L(C): " (source string S, line L, column
// C) or "S:L: " written as "FILE:L:C: " for the files the source strings are (`files`, by
// string number: 1 = common.glsl, 2 = the method's file, after pxh's #line directives; a
// plug-in's k-th other file is 2 + k, its lines numbered from kBodyLine (k + 1) + 1).
std::vector<std::string> located(const std::string& log, const std::map<int, std::string>& files,
                                 const BodyLines& body = {});

std::string joined(const std::vector<std::string>& lines);

// A compiled shader of `type` (GL_VERTEX_SHADER, GL_FRAGMENT_SHADER); a GlslProgramError with
// the driver's errors, located in `files`, when it does not compile.
unsigned compile(unsigned type, const std::string& src, const std::string& what,
                 const std::map<int, std::string>& files = {}, const BodyLines& body = {});

// Texture units: 0 the heights, 1 the view map, 2 - 4 the per-sample maps, then resources.
constexpr int kPointUnit = 2, kLodUnit = 3, kGradUnit = 4, kAxisUnit = 5, kFirstResourceUnit = 6;

}  // namespace pxh::glsl_detail
