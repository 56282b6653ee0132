// A gate's verdict in the forms CI systems read: JUnit XML (one testcase per limit of pxh check,
// one per compared row group of pxh compare; a failure carries the values) and JSON (the same,
// machine-readable). pxh check and pxh compare fill a Verdict; --junit FILE and --json FILE
// write it. Both files are created new (harness/core/safe_files.h): an existing file is
// replaced only when pxh wrote it (it carries pxh's mark), never one somebody else made.
#pragma once
#include <string>
#include <vector>

namespace pxh {

struct VerdictCase {
    std::string name;   // "err_p95 <= 0.5 on method=pom theta in [0, 60]"
    std::string group;  // the JUnit classname: "pxh.check" or "pxh.compare.METHOD"
    bool passed = true;
    std::string message;               // one line: why it failed (empty when passed)
    std::vector<std::string> details;  // the failing rows, values included
    // Numbers a machine may want (JSON only): e.g. worst, limit, rows.
    std::vector<std::pair<std::string, double>> values;
};

struct Verdict {
    std::string tool;     // "pxh check" | "pxh compare"
    std::string subject;  // what was judged: the results folder(s)
    int exit_code = 0;    // what the command returns
    std::string summary;  // the one verdict line the console prints
    std::vector<VerdictCase> cases;
    size_t failures() const;
};

// JUnit XML (the schema Jenkins, GitLab and GitHub's test reporters read): one <testsuite>
// named after the tool, a <testcase> per case, <failure message=...> with the details.
std::string junit_xml(const Verdict& v);
// {"tool", "subject", "passed", "exit_code", "summary", "failures", "cases": [...]}.
std::string verdict_json(const Verdict& v);

// Writes `text` to `path` (the option's name in errors: "--junit"). A file already there is
// replaced only when it is one pxh wrote (its mark: the tool's name in the first 256 bytes);
// anything else there is an InputError naming it. The write goes through a new file beside it
// and a rename, so the path holds the old verdict or the new one, never half of one.
void write_verdict_file(const std::string& path, const std::string& text, const char* option);

// --junit FILE and --json FILE naming the same file (as given, or through links and "..") is an
// InputError("--json", ...): the second verdict would replace the first. Called before any work.
void check_verdict_paths(const std::string& junit, const std::string& json);

}  // namespace pxh
