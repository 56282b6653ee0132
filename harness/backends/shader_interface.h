// The interface between a method and its linked GLSL program, checked from one place: the
// method's uniforms (methods/method.h: method_uniforms) and the harness's u_* uniforms must be
// exactly the program's active uniforms, each with its declared type. A declared uniform the
// program does not use, or an active uniform nobody sets, is an error naming the method, the
// uniform and the shader files, not a value GL silently drops.
#pragma once
#include <map>
#include <string>
#include <vector>

#include "methods/method.h"

namespace pxh {

// The uniforms the GLSL backend itself sets (methods/common.glsl declares them); any of them
// may be inactive in a program.
const std::vector<std::string>& harness_uniforms();

// A uniform as the program reports it: its GL type enum (GL_FLOAT, GL_INT, GL_BOOL,
// GL_SAMPLER_2D, ...).
struct ActiveUniform {
    unsigned gl_type = 0;
    int size = 1;
};

// The active uniforms of a linked program, by name (arrays as "a[0]"). Needs a current context.
std::map<std::string, ActiveUniform> active_uniforms(unsigned program);

// A uniform the method declares: its name and the GLSL type name it must have ("float",
// "int", "bool", "sampler2D").
struct DeclaredUniform {
    std::string name;
    std::string glsl_type;
};

// The problem with a program's interface, "" when none: the first declared uniform that is
// not active or has another type, declared twice, or the first active uniform that is neither
// declared nor the harness's. `what` names the method and the shader files.
std::string interface_problem(const std::map<std::string, ActiveUniform>& active,
                              const std::vector<DeclaredUniform>& declared,
                              const std::string& what);

// Every problem with a program's interface, in the order interface_problem finds the first:
// one line each (each unset active uniform its own).
std::vector<std::string> interface_problems(const std::map<std::string, ActiveUniform>& active,
                                            const std::vector<DeclaredUniform>& declared,
                                            const std::string& what);

// What must be active of a method's declared uniforms: all of them, except for a plug-in the
// engine uniforms its entry binds (names not p_NAME): one of the engine's modes reads such a
// uniform, another does not.
std::vector<DeclaredUniform> required_uniforms(const std::map<std::string, ActiveUniform>& active,
                                               const std::vector<DeclaredUniform>& declared,
                                               bool plugin);

// The GLSL type name of a GL type enum ("float", "int", "bool", "sampler2D", "vec3", ...).
std::string gl_type_name(unsigned gl_type);

// Sets each uniform with the glUniform call for its type (the program must be in use).
void set_method_uniforms(unsigned program, const GlUniforms& uniforms);

}  // namespace pxh
