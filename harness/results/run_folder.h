// A results folder: written whole or not at all, never over what pxh did not create, and
// checkable afterwards (run.json records the sha256 of every file the run wrote).
//
// A run writes into DIR.partial-PID-HEX beside DIR, a folder of a new name that this run's
// mkdir created (never one that exists: a leftover of the same name is never adopted), and
// renames it into place only when every file is written, flushed and fsync'ed. Every signal
// that ends a process (SIGINT, SIGTERM, SIGHUP, SIGQUIT, SIGUSR1/2, SIGALRM, SIGXCPU, ...; not
// SIGKILL and not a crash) removes the partial folder and the lock; SIGPIPE and SIGXFSZ are
// ignored, so the write fails and is reported. After a SIGKILL only DIR.partial-PID-HEX can
// remain, which the next run into the same parent mentions and pxh check refuses. One run at a
// time writes a given DIR (an advisory lock, released by the kernel when the process dies).
#pragma once
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

namespace pxh {

class RunFolder {
  public:
    // Checks `out` and reserves it: refuses (InputError naming it) the current folder or one
    // of its parents, a path that exists and is not a folder, a non-empty folder that is not a
    // pxh results folder (no run.json), and a pxh results folder unless `force`, which then
    // replaces only pxh's own files there: run.json, the files its "files" record lists
    // (results.csv, maps/, pictures/) whose bytes still match it, and report/; anything else
    // there (a file of yours in pictures/, a recorded file changed since, a link) refuses the
    // run, naming it. Installs the signal clean-up and creates the partial folder.
    RunFolder(const std::string& out, bool force);
    ~RunFolder();  // not committed: removes the partial folder
    RunFolder(const RunFolder&) = delete;
    RunFolder& operator=(const RunFolder&) = delete;

    const std::filesystem::path& partial() const { return tmp_; }
    const std::filesystem::path& final_dir() const { return final_; }

    // fsyncs every file and folder in the partial folder, puts it in place of DIR (an old
    // results folder being replaced is moved aside first and its pxh files deleted after),
    // fsyncs the parent. Throws std::runtime_error naming what failed; DIR then keeps what it had.
    void commit();

  private:
    std::filesystem::path final_, tmp_, lock_path_;
    int lock_fd_ = -1;
    bool replace_ = false;
};

// The integrity record of a folder's files (every regular file under `dir` except run.json,
// by path relative to `dir`): {"results.csv": {"bytes": N, "sha256": "..."}, ...}.
nlohmann::json file_records(const std::filesystem::path& dir);

// Verifies a results folder against its run.json (rows and sha256 of every recorded file).
// A mismatch, a missing file or a missing run.json is an InputError naming the file and what
// differs, unless accept_edited: then a warning goes to stderr and the returned line starts
// "NOT VERIFIED". On success returns "verified: ...".
std::string verify_results_folder(const std::string& dir, bool accept_edited);

}  // namespace pxh
