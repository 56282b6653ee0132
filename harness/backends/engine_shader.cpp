#include "harness/backends/engine_shader.h"

#include <cctype>
#include <filesystem>
#include <set>

#include "harness/backends/glsl_parts.h"
#include "harness/backends/plugin_source.h"
#include "harness/backends/shaders.h"
#include "harness/core/error.h"

namespace pxh {
namespace {

namespace fs = std::filesystem;
using glsl_detail::kBodyLine;

constexpr int kMaxIncludeDepth = 16;
constexpr const char* kAdapterFile = "pxh engine adapter (generated)";

bool ident_start(char c) { return std::isalpha(static_cast<unsigned char>(c)) || c == '_'; }
bool ident_char(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }

using Tok = ShaderToken;

std::vector<Tok> tokenize(const std::string& s) { return shader_tokens(s); }

}  // namespace

std::vector<ShaderToken> shader_tokens(const std::string& s) {
    std::vector<ShaderToken> out;
    int line = 1;
    size_t line_start = 0, i = 0;
    auto newline_at = [&](size_t k) {
        ++line;
        line_start = k + 1;
    };
    while (i < s.size()) {
        const char c = s[i];
        if (c == '\n') {
            newline_at(i++);
        } else if (c == '/' && i + 1 < s.size() && s[i + 1] == '/') {
            while (i < s.size() && s[i] != '\n') ++i;
        } else if (c == '/' && i + 1 < s.size() && s[i + 1] == '*') {
            i += 2;
            while (i < s.size() && !(s[i] == '*' && i + 1 < s.size() && s[i + 1] == '/'))
                if (s[i++] == '\n') newline_at(i - 1);
            i += 2;
        } else if (std::isspace(static_cast<unsigned char>(c))) {
            ++i;
        } else {
            size_t j = i + 1;
            if (ident_start(c) || std::isdigit(static_cast<unsigned char>(c)))
                while (j < s.size() && (ident_char(s[j]) || (!ident_start(c) && s[j] == '.'))) ++j;
            out.push_back({s.substr(i, j - i), i, j, line, int(i - line_start) + 1});
            i = j;
        }
    }
    return out;
}

namespace {

// The sampling calls pxh counts, by what they read: the row's lod, an explicit level,
// explicit derivatives; and textureSize (no fetch).
enum class Call { Implicit, Level, Grad, Size };
const std::map<std::string, Call>& sampling_calls() {
    static const std::map<std::string, Call> m = {
        {"texture", Call::Implicit},       {"texture2D", Call::Implicit},
        {"texture2DBias", Call::Implicit}, {"textureLod", Call::Level},
        {"texture2DLod", Call::Level},     {"texture2DLodEXT", Call::Level},
        {"textureGrad", Call::Grad},       {"texture2DGradEXT", Call::Grad},
        {"textureSize", Call::Size}};
    return m;
}
const char* replacement(Call c) {
    switch (c) {
        case Call::Implicit:
            return "pxh_engine_height(";
        case Call::Level:
            return "pxh_engine_height_lod(";
        case Call::Grad:
            return "pxh_engine_height_grad(";
        case Call::Size:
            return "pxh_height_size(";
    }
    return "";
}

std::string call_names() {
    std::string s;
    for (const auto& [name, c] : sampling_calls()) s += (s.empty() ? "" : ", ") + name;
    return s;
}

// `{NAME}` replaced by the value of define NAME (PlayCanvas's chunk parameters).
std::string substitute_braces(const std::string& s, const EngineAdapter& a) {
    std::string out;
    size_t i = 0;
    while (i < s.size()) {
        bool done = false;
        if (s[i] == '{' && i + 1 < s.size() && ident_start(s[i + 1])) {
            size_t j = i + 1;
            while (j < s.size() && ident_char(s[j])) ++j;
            if (j < s.size() && s[j] == '}') {
                const std::string name = s.substr(i + 1, j - i - 1);
                for (const auto& [k, v] : a.defines)
                    if (k == name) {
                        out += v;
                        i = j + 1;
                        done = true;
                        break;
                    }
            }
        }
        if (!done) out += s[i++];
    }
    return out;
}

// What the rewriting of all files gathers.
struct Gathered {
    std::map<std::string, std::string> uniform_types;  // declared uniform -> its type
    std::string explicit_level;                        // the first explicit-level call
    EngineNames names;                                 // identifiers off #if / #elif lines
};

// For each line (1-based), whether it is an #if or #elif directive.
std::vector<bool> conditional_lines(const std::string& text) {
    std::vector<bool> out{false};
    size_t start = 0;
    while (start <= text.size()) {
        size_t end = text.find('\n', start);
        if (end == std::string::npos) end = text.size();
        size_t i = text.find_first_not_of(" \t", start);
        bool cond = false;
        if (i < end && text[i] == '#') {
            i = text.find_first_not_of(" \t", i + 1);
            cond = i < end && (text.compare(i, 2, "if") == 0 || text.compare(i, 4, "elif") == 0) &&
                   text.compare(i, 5, "ifdef") != 0 && text.compare(i, 6, "ifndef") != 0;
        }
        out.push_back(cond);
        start = end + 1;
    }
    return out;
}

std::string at(const std::string& display, const Tok& t) {
    return display + ":" + std::to_string(t.line) + ":" + std::to_string(t.col);
}

// The uniform declaration at token i (`uniform [precision] TYPE NAME ...`): its type and
// the index of its name; false when it is none.
bool uniform_decl(const std::vector<Tok>& t, size_t i, std::string& type, size_t& name) {
    if (t[i].text != "uniform") return false;
    size_t j = i + 1;
    while (j < t.size() && (t[j].text == "lowp" || t[j].text == "mediump" || t[j].text == "highp"))
        ++j;
    if (j + 1 >= t.size() || !ident_start(t[j + 1].text[0])) return false;
    type = t[j].text;
    name = j + 1;
    return true;
}

// One file's text with the adapter's changes, at the same lines: sampling calls on the height
// sampler made pxh's, `uniform` dropped from declarations bound to quantities, pxh_method
// renamed when the adapter defines it.
std::string rewrite(const std::string& text, const std::string& display, const EngineAdapter& a,
                    Gathered& g) {
    const std::vector<Tok> t = tokenize(text);
    const std::vector<bool> conditional = conditional_lines(text);
    for (const Tok& k : t)
        if (ident_start(k.text[0]) && !conditional[size_t(k.line)]) g.names.code.insert(k.text);
    std::string out;
    size_t copied = 0;
    auto replace = [&](size_t from, size_t to, const std::string& with) {
        out += text.substr(copied, from - copied) + with;
        copied = to;
    };
    for (size_t i = 0; i < t.size(); ++i) {
        std::string type;
        size_t name = 0;
        if (uniform_decl(t, i, type, name)) {
            g.uniform_types.emplace(t[name].text, type);
            if (a.quantities.count(t[name].text)) {
                if (name + 1 < t.size() && t[name + 1].text != ";")
                    throw InputError(at(display, t[name]),
                                     "uniform '" + t[name].text +
                                         "' is bound to a scene quantity: declare it on its own "
                                         "(`uniform " +
                                         type + " " + t[name].text + ";`)");
                replace(t[i].begin, t[i].end, "");  // a global the adapter sets
            }
            continue;
        }
        if (!a.quantities.empty() && t[i].text == "pxh_method") {
            replace(t[i].begin, t[i].end, "pxh_engine_method");
            continue;
        }
        if (t[i].text == "pxh_height_lod" && g.explicit_level.empty())
            g.explicit_level = at(display, t[i]) + ": pxh_height_lod";
        if (a.height_sampler.empty()) continue;
        // A call with the sampler first: a GLSL sampling built-in (texture*, texel*), not a
        // function of the shader's own (which is the sampler passed on, refused below).
        const bool builtin = t[i].text.rfind("texture", 0) == 0 || t[i].text.rfind("texel", 0) == 0;
        const bool call = builtin && i + 3 < t.size() && t[i + 1].text == "(" &&
                          t[i + 2].text == a.height_sampler && t[i + 3].text == ",";
        if (call) {
            const auto c = sampling_calls().find(t[i].text);
            if (c == sampling_calls().end())
                throw InputError(at(display, t[i]),
                                 "'" + t[i].text + "' on the height sampler '" + a.height_sampler +
                                     "' is not a call pxh counts (" + call_names() + ")");
            if (c->second == Call::Level && g.explicit_level.empty())
                g.explicit_level = at(display, t[i]) + ": " + t[i].text;
            replace(t[i].begin, t[i + 3].end, replacement(c->second));
            i += 3;
            continue;
        }
        if (t[i].text == a.height_sampler && !(i > 0 && t[i - 1].text == "sampler2D"))
            throw InputError(at(display, t[i]),
                             "the height sampler '" + a.height_sampler +
                                 "' is used here other than as the first argument of a sampling "
                                 "call pxh counts (" +
                                 call_names() +
                                 "); pxh counts the fetches where the sampler is sampled by name");
    }
    out += text.substr(copied);
    return out;
}

struct Expansion {
    const std::string& experiment_path;
    const EngineAdapter& a;
    EngineShader& shader;
    Gathered g;
    std::vector<std::string> resolved;  // each file read, by canonical path (index = k)
    std::vector<std::string> stack;     // the includes being expanded
};

std::string line_directive(size_t k, long line) {
    return "#line " + std::to_string(kBodyLine * long(k + 1) + line) + " " + std::to_string(k + 2) +
           "\n";
}

void expand(Expansion& e, const std::string& rel, const std::string& text, size_t k,
            std::string& out);

// The file an #include names, read and expanded in place of its line.
void include_file(Expansion& e, const std::string& includer_rel, const std::string& name,
                  bool angle, const std::string& where, std::string& out, size_t parent,
                  long line) {
    std::string rel;
    if (const auto it = e.a.includes.find(name); it != e.a.includes.end()) rel = it->second;
    else if (angle)
        throw InputError(where, "#include <" + name +
                                    ">: no such name in the entry's includes (map it to a file: "
                                    "includes = { " +
                                    name + " = \"FILE\" })");
    else rel = (fs::path(includer_rel).parent_path() / name).lexically_normal().string();
    if (e.stack.size() >= size_t(kMaxIncludeDepth))
        throw InputError(where, "#include nested deeper than " + std::to_string(kMaxIncludeDepth));
    const PluginSource src = read_plugin_source(e.experiment_path, rel, where);
    for (const std::string& r : e.stack)
        if (r == src.resolved)
            throw InputError(
                where, "#include \"" + name + "\" includes itself (through " + src.display + ")");
    size_t k = 0;
    while (k < e.resolved.size() && e.resolved[k] != src.resolved) ++k;
    if (k == e.resolved.size()) {
        e.resolved.push_back(src.resolved);
        e.shader.files.push_back(src.display);
        e.shader.texts.push_back(src.text);
    }
    e.stack.push_back(src.resolved);
    out += line_directive(k, 1);
    expand(e, rel, src.text, k, out);
    out += "\n" + line_directive(parent, line + 1);
    e.stack.pop_back();
}

void expand(Expansion& e, const std::string& rel, const std::string& text, size_t k,
            std::string& out) {
    const std::string& display = e.shader.files[k];
    if (const auto problems =
            plugin_source_problems(display, text, shader_source("methods/common.glsl", "").text);
        !problems.empty()) {
        const size_t colon = problems[0].find(": ");
        throw InputError(problems[0].substr(0, colon), problems[0].substr(colon + 2));
    }
    const std::string body = rewrite(substitute_braces(text, e.a), display, e.a, e.g);
    size_t start = 0;
    long line = 1;
    while (start <= body.size()) {
        size_t end = body.find('\n', start);
        if (end == std::string::npos) end = body.size();
        const std::string l = body.substr(start, end - start);
        std::string name, problem;
        bool angle = false;
        if (engine_include_line(l, name, angle, problem)) {
            const std::string where = display + ":" + std::to_string(line);
            if (!problem.empty()) throw InputError(where, problem);
            include_file(e, rel, name, angle, where, out, k, line);
        } else {
            out += l;
            if (end < body.size()) out += "\n";
        }
        start = end + 1;
        ++line;
    }
}

}  // namespace

std::string engine_define_lines(const EngineAdapter& a, const EngineNames& names) {
    std::string s;
    for (const auto& [name, value] : a.defines) s += "#define " + name + " " + value + "\n";
    // Names not to define: the defines themselves, the code's names, and the values of the
    // defines the code expands (CHANNEL = "g" in `.CHANNEL`: g is a swizzle, not a mode).
    std::set<std::string> keep = names.code;
    for (const auto& [name, value] : a.defines) {
        keep.insert(name);
        if (names.code.count(name)) keep.insert(value);
    }
    int n = 0;
    for (const std::string& name : a.define_names)
        if (!keep.count(name)) s += "#define " + name + " " + std::to_string(++n) + "\n";
    return s;
}

EngineNames engine_names(const std::string& text) {
    EngineNames out;
    const std::vector<bool> conditional = conditional_lines(text);
    for (const Tok& k : tokenize(text))
        if (ident_start(k.text[0]) && !conditional[size_t(k.line)]) out.code.insert(k.text);
    return out;
}

bool engine_include_line(const std::string& line, std::string& name, bool& angle,
                         std::string& problem) {
    size_t i = line.find_first_not_of(" \t");
    if (i == std::string::npos || line[i] != '#') return false;
    i = line.find_first_not_of(" \t", i + 1);
    if (i == std::string::npos || line.compare(i, 7, "include") != 0) return false;
    i = line.find_first_not_of(" \t", i + 7);
    const char open = i == std::string::npos ? '\0' : line[i];
    if (open != '"' && open != '<') {
        problem = "#include needs \"file\" or <name>";
        return true;
    }
    angle = open == '<';
    const size_t close = line.find(angle ? '>' : '"', i + 1);
    if (close == std::string::npos) {
        problem = std::string("#include: no closing ") + (angle ? ">" : "\"");
        return true;
    }
    name = line.substr(i + 1, close - i - 1);
    std::string rest = line.substr(close + 1);
    if (const size_t c = rest.find("//"); c != std::string::npos) rest.resize(c);
    if (rest.find_first_not_of(" \t\r") != std::string::npos)
        problem = "#include " + line.substr(i, close - i + 1) +
                  " is followed by more (an engine's include parameters, such as Babylon's "
                  "[0..n] or (a,b), are not supported): write the included text out";
    if (name.empty()) problem = "#include names nothing";
    return true;
}

namespace {

std::string adapter_prelude(const EngineAdapter& a, const EngineNames& names) {
    std::string s = "// pxh's adapter of an engine's shader (docs/guide/plugin-shaders.md)\n";
    s += engine_define_lines(a, names);
    std::string v = a.depth ? "1.0 - h" : "h";
    if (a.channel >= 0) {
        s += "vec4 pxh_engine_texel(float h) {\n    vec4 t = vec4(0.0);\n    t[" +
             std::to_string(a.channel) + "] = " + v + ";\n    return t;\n}\n";
    } else {
        s += "vec4 pxh_engine_texel(float h) { return vec4(" + v + "); }\n";
    }
    s += "vec4 pxh_engine_height(vec2 uv) { return pxh_engine_texel(pxh_height(uv)); }\n"
         "vec4 pxh_engine_height(vec2 uv, float bias) { return pxh_engine_texel(pxh_height(uv)); "
         "}\n"
         "vec4 pxh_engine_height_lod(vec2 uv, float lod) {\n"
         "    return pxh_engine_texel(pxh_height_lod(uv, lod));\n}\n"
         "vec4 pxh_engine_height_grad(vec2 uv, vec2 dx, vec2 dy) {\n"
         "    return pxh_engine_texel(pxh_height_grad(uv, dx, dy));\n}\n";
    return s;
}

}  // namespace

bool EngineAdapter::plain() const {
    return height_sampler.empty() && quantities.empty() && defines.empty() && includes.empty();
}

std::string quantity_glsl(const std::string& q, std::string& problem) {
    std::string out;
    int depth = 0;
    bool operand = false;  // the last token ends an operand
    for (const Tok& t : tokenize(q)) {
        const std::string& x = t.text;
        if (x == "scale" || x == "bias" || std::isdigit(static_cast<unsigned char>(x[0]))) {
            if (operand) break;
            if (x == "scale" || x == "bias") out += "u_" + x;
            else if (x.find_first_not_of("0123456789.") != std::string::npos) break;
            else out += x.find('.') == std::string::npos ? x + ".0" : x;
            operand = true;
        } else if (x == "(" || x == ")") {
            depth += x == "(" ? 1 : -1;
            if (depth < 0 || (x == "(" && operand) || (x == ")" && !operand)) break;
            out += x;
        } else if (x == "+" || x == "-" || x == "*" || x == "/") {
            if (!operand && x != "-") break;
            out += " " + x + " ";
            operand = false;
        } else {
            out.clear();
            break;
        }
        if (x == "(") operand = false;
    }
    if (out.empty() || depth != 0 || !operand) {
        problem = "'" + q +
                  "' is not a scene quantity: write scale or bias, or an expression of them with "
                  "numbers, + - * / and parentheses (e.g. \"scale / 0.1\")";
        return "";
    }
    return "(" + out + ")";
}

EngineShader adapt_engine_shader(const std::string& experiment_path, const std::string& main_rel,
                                 const std::string& main_text, const std::string& main_display,
                                 const EngineAdapter& a, const std::string& where) {
    EngineShader shader;
    shader.files = {main_display};
    shader.texts = {main_text};
    Expansion e{experiment_path, a, shader, {}, {""}, {}};
    std::string body;
    expand(e, main_rel, main_text, 0, body);
    shader.uniform_types = e.g.uniform_types;
    shader.explicit_level = e.g.explicit_level;
    if (a.plain() && shader.files.size() == 1) {  // nothing to adapt: the text as it is
        shader.text = main_text;
        return shader;
    }
    for (const auto& [name, expr] : a.quantities)
        if (!e.g.uniform_types.count(name))
            throw InputError(
                where, "bind: '" + name + "' is not a uniform the shader or its includes declare");
    const size_t adapter = shader.files.size();
    shader.files.push_back(kAdapterFile);
    std::string text = line_directive(adapter, 1) + adapter_prelude(a, e.g.names);
    text += line_directive(0, 1) + body + "\n";
    if (!a.quantities.empty()) {
        text += line_directive(adapter, 1000) + "vec2 pxh_method(vec2 P) {\n";
        for (const auto& [name, expr] : a.quantities)
            text += "    " + name + " = " + e.g.uniform_types[name] + expr + ";\n";
        text += "    return pxh_engine_method(P);\n}\n";
    }
    shader.text = std::move(text);
    return shader;
}

}  // namespace pxh
