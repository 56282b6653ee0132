// A shader converter run as a child process (glslangValidator, spirv-cross, node): its argument
// vector passed as it is (no shell), found on PATH, its output and errors read back from files.
#pragma once
#include <string>
#include <vector>

namespace pxh {

struct ToolResult {
    bool started = false;  // false: the program is not installed (or could not be run)
    int exit_code = -1;    // -1: killed (the time limit) or ended by a signal
    std::string output;    // stdout and stderr, in that order
};

// Runs argv[0] (searched on PATH) with `argv` (paths in it absolute), its output written to a
// file in the folder `dir`, for at most
// `time_limit_s` seconds (then killed).
ToolResult run_tool(const std::vector<std::string>& argv, const std::string& dir,
                    double time_limit_s = 60.0);

// A fresh private folder under the system's temporary folder, removed when this goes.
class TempFolder {
  public:
    TempFolder();
    ~TempFolder();
    TempFolder(const TempFolder&) = delete;
    TempFolder& operator=(const TempFolder&) = delete;
    const std::string& path() const { return path_; }
    // Writes `text` to the file `name` in the folder; returns its path.
    std::string write(const std::string& name, const std::string& text) const;
    // The text of the file `name` in the folder ("" when there is none).
    std::string read(const std::string& name) const;

  private:
    std::string path_;
};

}  // namespace pxh
