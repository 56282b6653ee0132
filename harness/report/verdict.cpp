#include "harness/report/verdict.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <system_error>

#include "harness/core/error.h"
#include "harness/core/safe_files.h"

namespace pxh {
namespace {

constexpr const char* kMark = "pxh verdict";  // in the first bytes of every file written here

std::string xml_escaped(const std::string& s) {
    std::string out;
    for (const char c : s) {
        switch (c) {
            case '&':
                out += "&amp;";
                break;
            case '<':
                out += "&lt;";
                break;
            case '>':
                out += "&gt;";
                break;
            case '"':
                out += "&quot;";
                break;
            case '\'':
                out += "&apos;";
                break;
            default:
                // XML 1.0 has no control characters but tab and newline.
                if (static_cast<unsigned char>(c) < 0x20 && c != '\n' && c != '\t') out += ' ';
                else out += c;
        }
    }
    return out;
}

}  // namespace

size_t Verdict::failures() const {
    size_t n = 0;
    for (const VerdictCase& c : cases) n += !c.passed;
    return n;
}

std::string junit_xml(const Verdict& v) {
    std::ostringstream x;
    x << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<!-- " << kMark << ": " << v.tool << " -->\n";
    x << "<testsuites name=\"" << xml_escaped(v.tool) << "\" tests=\"" << v.cases.size()
      << "\" failures=\"" << v.failures() << "\" errors=\"0\">\n";
    x << "  <testsuite name=\"" << xml_escaped(v.tool + " " + v.subject) << "\" tests=\""
      << v.cases.size() << "\" failures=\"" << v.failures() << "\" errors=\"0\" skipped=\"0\">\n";
    x << "    <properties><property name=\"summary\" value=\"" << xml_escaped(v.summary)
      << "\"/></properties>\n";
    for (const VerdictCase& c : v.cases) {
        x << "    <testcase classname=\"" << xml_escaped(c.group) << "\" name=\""
          << xml_escaped(c.name) << "\"";
        if (c.passed) {
            x << "/>\n";
            continue;
        }
        x << ">\n      <failure message=\"" << xml_escaped(c.message) << "\" type=\"regression\">";
        for (size_t i = 0; i < c.details.size(); ++i)
            x << (i ? "\n" : "") << xml_escaped(c.details[i]);
        x << "</failure>\n    </testcase>\n";
    }
    x << "  </testsuite>\n</testsuites>\n";
    return x.str();
}

std::string verdict_json(const Verdict& v) {
    nlohmann::ordered_json j;
    j["format"] = std::string(kMark) + " 1";
    j["tool"] = v.tool;
    j["subject"] = v.subject;
    j["passed"] = v.exit_code == 0;
    j["exit_code"] = v.exit_code;
    j["summary"] = v.summary;
    j["failures"] = v.failures();
    j["cases"] = nlohmann::ordered_json::array();
    for (const VerdictCase& c : v.cases) {
        nlohmann::ordered_json e;
        e["name"] = c.name;
        e["group"] = c.group;
        e["passed"] = c.passed;
        if (!c.message.empty()) e["message"] = c.message;
        if (!c.details.empty()) e["details"] = c.details;
        for (const auto& [k, value] : c.values)
            e[k] = std::isfinite(value) ? nlohmann::ordered_json(value) : nullptr;
        j["cases"].push_back(std::move(e));
    }
    return j.dump(2) + "\n";
}

void write_verdict_file(const std::string& path, const std::string& text, const char* option) {
    if (path.empty()) throw InputError(option, "an empty file name");
    const auto marked = [](const std::filesystem::path& p) {
        std::ifstream in(p, std::ios::binary);
        std::string head(256, '\0');
        in.read(head.data(), std::streamsize(head.size()));
        head.resize(size_t(in.gcount()));
        return head.find(kMark) != std::string::npos;
    };
    try {
        replace_own_file(path, text, marked, option,
                         path +
                             " exists and is not a verdict pxh wrote: not replaced (name a "
                             "new file, or remove it yourself)");
    } catch (const InputError&) {
        throw;
    } catch (const std::exception& e) {
        throw InputError(option, e.what());
    }
}

void check_verdict_paths(const std::string& junit, const std::string& json) {
    namespace fs = std::filesystem;
    if (junit.empty() || json.empty()) return;
    std::error_code e1, e2;
    const fs::path a = fs::weakly_canonical(fs::absolute(junit), e1);
    const fs::path b = fs::weakly_canonical(fs::absolute(json), e2);
    const bool same =
        junit == json || (!e1 && !e2 && a == b) ||
        (fs::exists(junit, e1) && fs::exists(json, e2) && fs::equivalent(junit, json, e1));
    if (same)
        throw InputError("--json", "'" + json +
                                       "' is also the --junit file: the JSON verdict "
                                       "would replace the JUnit one (give two files)");
}

}  // namespace pxh
