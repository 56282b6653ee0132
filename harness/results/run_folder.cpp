#include "harness/results/run_folder.h"

#include <dirent.h>
#include <fcntl.h>
#include <pthread.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <mutex>
#include <set>
#include <sstream>
#include <thread>

#include "harness/core/error.h"
#include "harness/core/safe_files.h"
#include "harness/core/sha256.h"
#include "harness/results/csv_table.h"

namespace pxh {
namespace {

namespace fs = std::filesystem;

// What pxh report writes into a results folder (report/, whole): --force removes it with the
// run's own files. Every other file --force removes is one run.json's "files" record lists.
const char* const kReportEntry = "report";

std::string errno_text() { return std::strerror(errno); }

// Signal clean-up: every signal whose default action ends the process, except the ones a
// fault raises (SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGTRAP, SIGSYS, SIGABRT) and SIGKILL, is
// blocked in every thread (the mask is inherited by TBB's and llvmpipe's workers, created
// later) and taken by one thread with sigwait, which runs in normal context, so it may remove
// the partial folder and the lock file. SIGPIPE and SIGXFSZ are ignored instead: the write
// then fails (EPIPE, EFBIG) and is reported as a write error. `mu` orders the clean-up
// against commit.
struct SignalState {
    std::mutex mu;
    fs::path tmp, lock_path;
    bool active = false, committed = false;
};
SignalState& signal_state() {
    static SignalState s;
    return s;
}

sigset_t ending_signals() {
    sigset_t set;
    sigemptyset(&set);
    for (int sig : {SIGINT, SIGTERM, SIGHUP, SIGQUIT, SIGUSR1, SIGUSR2, SIGALRM, SIGVTALRM, SIGPROF,
                    SIGXCPU, SIGPWR, SIGIO, SIGSTKFLT})
        sigaddset(&set, sig);
    for (int sig = SIGRTMIN; sig <= SIGRTMAX; ++sig) sigaddset(&set, sig);
    return set;
}

void install_signal_cleanup() {
    static std::once_flag once;
    std::call_once(once, [] {
        ignore_write_signals();
        const sigset_t set = ending_signals();
        pthread_sigmask(SIG_BLOCK, &set, nullptr);
        std::thread([set] {
            int sig = 0;
            while (sigwait(&set, &sig) != 0) {
            }
            SignalState& s = signal_state();
            std::lock_guard<std::mutex> lock(s.mu);
            if (s.active) {
                std::error_code ec;
                if (!s.committed) fs::remove_all(s.tmp, ec);
                fs::remove(s.lock_path, ec);
                if (!s.committed)
                    std::cerr << "\npxh: interrupted (signal " << sig << ", " << strsignal(sig)
                              << "); removed " << s.tmp.string() << ", no results written\n";
            }
            _exit(128 + sig);
        }).detach();
    });
}

// pid of a NAME.partial-PID[-HEX] / NAME.replaced-PID[-HEX] folder, or -1.
long pid_suffix(const std::string& name, const std::string& kind) {
    const size_t at = name.rfind(kind);
    if (at == std::string::npos || at == 0 || at + kind.size() == name.size()) return -1;
    std::string digits = name.substr(at + kind.size());
    if (const size_t dash = digits.find('-'); dash != std::string::npos) {
        const std::string hex = digits.substr(dash + 1);
        if (hex.empty() || hex.find_first_not_of("0123456789abcdef") != std::string::npos)
            return -1;
        digits.resize(dash);
    }
    if (digits.empty() || digits.find_first_not_of("0123456789") != std::string::npos ||
        digits.size() > 9)
        return -1;
    return std::stol(digits);
}

// Names the folders beside final_dir that interrupted runs left (their process is gone).
void warn_stale_siblings(const fs::path& final_dir) {
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(final_dir.parent_path(), ec)) {
        if (!e.is_directory(ec) || e.is_symlink(ec)) continue;
        const std::string name = e.path().filename().string();
        for (const std::string kind : {".partial-", ".replaced-"}) {
            const long pid = pid_suffix(name, kind);
            if (pid <= 0) continue;
            if (::kill(pid_t(pid), 0) == 0 || errno != ESRCH) continue;  // its run is alive
            std::cerr << "pxh: warning: " << e.path().string()
                      << " is left from an interrupted run "
                      << "(pid " << pid << ", no longer running)"
                      << (kind == ".partial-" ? ": its results are incomplete"
                                              : ": it holds the results that run was replacing")
                      << "; pxh leaves it: delete it when you no longer need it\n";
        }
    }
}

// The files and folders of an earlier results folder that --force would remove: run.json,
// every file its "files" record lists whose bytes still match the record, report/ (pxh
// report's), and the folders holding them. Anything else (a file the record does not list, a
// recorded file changed since, a link, a FIFO) is an InputError naming it: pxh removes only
// its own files.
struct OwnEntries {
    std::vector<fs::path> files;    // relative to the folder
    std::vector<fs::path> folders;  // relative, deepest last
    bool report = false;            // report/ (removed whole)
};

// report/ is pxh report's: removed whole only when every entry in it is listed in its
// manifest.txt (what pxh report wrote there); anything else is the user's and refuses --force.
template <class Refuse>
void check_report_entries(const fs::path& report, const Refuse& refuse) {
    std::set<std::string> listed;
    try {
        listed = OwnedFolder::listed(report);
    } catch (const InputError&) {
        throw refuse(fs::path(kReportEntry) / OwnedFolder::kManifest,
                     "which is not the manifest pxh report writes");
    }
    for (auto it = fs::recursive_directory_iterator(report);
         it != fs::recursive_directory_iterator(); ++it) {
        const std::string rel = it->path().lexically_relative(report).generic_string();
        const auto st = it->symlink_status();
        const fs::path shown = fs::path(kReportEntry) / rel;
        if (rel == OwnedFolder::kManifest) continue;
        if (fs::is_symlink(st)) throw refuse(shown, "a symbolic link pxh did not write");
        if (fs::is_directory(st) ? !listed.count(rel + "/") : !listed.count(rel))
            throw refuse(shown,
                         "which pxh report did not write there (report/manifest.txt does not "
                         "list it)");
    }
}

OwnEntries own_entries(const fs::path& dir) {
    auto refuse = [&](const fs::path& rel, const std::string& why) {
        return InputError(dir.string(), "--force would delete '" + rel.generic_string() + "', " +
                                            why + "; move it away or choose another --out");
    };
    OwnEntries own;
    nlohmann::json files = nlohmann::json::object();
    {
        const fs::path run_json = dir / "run.json";
        if (!fs::is_regular_file(fs::symlink_status(run_json)))
            throw refuse("run.json", "which is not a regular file pxh wrote");
        nlohmann::json run;
        try {
            std::ifstream f(run_json, std::ios::binary);
            run = nlohmann::json::parse(f);
        } catch (const std::exception&) {
            throw refuse("run.json", "which does not read as pxh's run.json");
        }
        if (run.is_object() && run.contains("files") && run["files"].is_object())
            files = run["files"];
        else if (run.is_object())  // an older pxh: no record of its files but results.csv
            files["results.csv"] = nullptr;
        else throw refuse("run.json", "which does not read as pxh's run.json");
    }
    for (auto it = fs::recursive_directory_iterator(dir); it != fs::recursive_directory_iterator();
         ++it) {
        const fs::path rel = it->path().lexically_relative(dir);
        const std::string name = rel.generic_string();
        const auto st = it->symlink_status();
        if (name == kReportEntry) {
            if (!fs::is_directory(st))
                throw refuse(rel, "which is not the folder pxh report writes");
            check_report_entries(dir / kReportEntry, refuse);
            own.report = true;
            it.disable_recursion_pending();
            continue;
        }
        if (fs::is_symlink(st)) throw refuse(rel, "a symbolic link pxh did not write");
        if (fs::is_directory(st)) {
            own.folders.push_back(rel);
            continue;
        }
        if (!fs::is_regular_file(st)) throw refuse(rel, "which is not a file pxh wrote");
        if (name == "run.json") {
            own.files.push_back(rel);
            continue;
        }
        if (!files.contains(name))
            throw refuse(rel, "which pxh did not write there (run.json does not record it)");
        const auto& rec = files[name];
        if (rec.is_object() && rec.contains("sha256") && rec["sha256"].is_string() &&
            sha256_file(it->path().string()) != rec["sha256"].get<std::string>())
            throw refuse(rel,
                         "which has changed since pxh wrote it (its sha256 differs from "
                         "run.json's record)");
        own.files.push_back(rel);
    }
    std::sort(own.folders.begin(), own.folders.end(), [](const fs::path& a, const fs::path& b) {
        return std::distance(a.begin(), a.end()) > std::distance(b.begin(), b.end());
    });
    return own;
}

// Removes what own_entries found from `dir` (moved aside), then the folder itself; returns
// false if something else is left (it appeared meanwhile), which stays.
bool remove_own(const fs::path& dir, const OwnEntries& own) {
    std::error_code ec;
    for (const auto& f : own.files) fs::remove(dir / f, ec);
    if (own.report) fs::remove_all(dir / kReportEntry, ec);
    bool all = true;
    for (const auto& d : own.folders)  // deepest first; rmdir fails on a non-empty folder
        if (::rmdir((dir / d).c_str()) != 0 && errno != ENOENT) all = false;
    return ::rmdir(dir.c_str()) == 0 && all;
}

// The lock file of `final_dir`, held (flock) by this process: created without following a
// link; re-opened if another run removed it between our open and our lock.
int take_lock(const fs::path& lock_path, const std::string& out) {
    for (int attempt = 0; attempt < 10; ++attempt) {
        const int fd = ::open(lock_path.c_str(), O_RDWR | O_CREAT | O_NOFOLLOW | O_CLOEXEC, 0644);
        if (fd < 0)
            throw InputError(lock_path.string(), "cannot create the lock file: " + errno_text());
        if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
            ::close(fd);
            throw InputError(out, "another pxh run is writing this folder now (it holds " +
                                      lock_path.string() +
                                      "); wait for it or choose another --out");
        }
        struct stat held, named;
        if (::fstat(fd, &held) == 0 && ::lstat(lock_path.c_str(), &named) == 0 &&
            held.st_dev == named.st_dev && held.st_ino == named.st_ino)
            return fd;
        ::close(fd);  // the file we locked is no longer the one of that name: again
    }
    throw InputError(lock_path.string(), "cannot take the lock file (it keeps being replaced)");
}

}  // namespace

RunFolder::RunFolder(const std::string& out, bool force) {
    if (out.empty()) throw InputError("--out", "is empty: name the results folder");
    fs::path p = fs::absolute(out).lexically_normal();
    if (p.filename().empty()) p = p.parent_path();  // "runs/x/" -> "runs/x"
    final_ = fs::weakly_canonical(p);
    const fs::path cwd = fs::weakly_canonical(fs::current_path());
    // The current folder, or a folder holding it, is never a results folder.
    const auto rel = cwd.lexically_relative(final_);
    if (final_ == final_.root_path() || (!rel.empty() && *rel.begin() != ".."))
        throw InputError(out,
                         "is the current folder or one of its parents: results go into a new "
                         "folder of their own (e.g. --out results/runs/NAME)");
    std::error_code ec;
    const auto st = fs::symlink_status(p, ec);
    if (fs::exists(st)) {
        if (fs::is_symlink(st)) throw InputError(out, "is a symbolic link; name the folder itself");
        if (!fs::is_directory(st)) throw InputError(out, "exists and is not a folder");
    }
    fs::create_directories(final_.parent_path());

    // Installed first: from the lock file on, a signal removes what this run created.
    install_signal_cleanup();
    SignalState& s = signal_state();
    // One writer per DIR: an advisory lock on PARENT/.NAME.pxh-lock (freed if we die).
    lock_path_ = final_.parent_path() / ("." + final_.filename().string() + ".pxh-lock");
    {
        std::lock_guard<std::mutex> lock(s.mu);
        lock_fd_ = take_lock(lock_path_, out);
        s.tmp.clear();
        s.lock_path = lock_path_;
        s.active = true;
        s.committed = false;
    }
    try {
        if (fs::is_directory(final_) && !fs::is_empty(final_)) {
            if (!fs::exists(fs::symlink_status(final_ / "run.json")))
                throw InputError(out,
                                 "exists, is not empty and is not a pxh results folder (no "
                                 "run.json); pxh never deletes what it did not create: choose "
                                 "another --out");
            if (!force)
                throw InputError(out,
                                 "holds earlier pxh results (run.json); pass --force to replace "
                                 "them, or choose another --out");
            own_entries(final_);  // only pxh's own files there, or refused now
            replace_ = true;
        }
        warn_stale_siblings(final_);

        // A folder of a new name, made by this mkdir (never one that exists: never adopted).
        std::lock_guard<std::mutex> lock(s.mu);
        tmp_ = make_unique_folder(final_.string() + ".partial-" + std::to_string(getpid()));
        s.tmp = tmp_;
    } catch (...) {
        // No destructor runs for a constructor that throws: the lock goes here.
        std::lock_guard<std::mutex> lock(s.mu);
        s.active = false;
        fs::remove(lock_path_, ec);
        ::close(lock_fd_);
        lock_fd_ = -1;
        throw;
    }
}

RunFolder::~RunFolder() {
    SignalState& s = signal_state();
    std::lock_guard<std::mutex> lock(s.mu);
    std::error_code ec;
    if (s.active && !s.committed && !tmp_.empty()) fs::remove_all(tmp_, ec);
    s.active = false;
    if (lock_fd_ >= 0) {
        fs::remove(lock_path_, ec);
        ::close(lock_fd_);
    }
}

void RunFolder::commit() {
    sync_tree(tmp_);
    SignalState& s = signal_state();
    std::lock_guard<std::mutex> lock(s.mu);
    fs::path aside;
    OwnEntries own;
    if (replace_) {
        own = own_entries(final_);  // still only pxh's files (checked again: time has passed)
        try {                       // moved aside under a name of its own (nothing is replaced)
            aside = move_aside(final_, "replaced");
        } catch (const std::exception& e) {
            throw std::runtime_error(std::string(e.what()) + " (the complete results stay in " +
                                     tmp_.string() + ")");
        }
    }
    std::error_code ec;
    fs::rename(tmp_, final_, ec);  // replaces an empty folder; fails on a non-empty one
    if (ec) {
        if (!aside.empty()) fs::rename(aside, final_);
        throw std::runtime_error("cannot move " + tmp_.string() + " to " + final_.string() + ": " +
                                 ec.message() + " (the complete results stay in " + tmp_.string() +
                                 ")");
    }
    s.committed = true;
    fsync_path(final_.parent_path(), true);
    if (!aside.empty() && !remove_own(aside, own))
        std::cerr << "pxh: warning: " << aside.string()
                  << " keeps what appeared in the old results folder while this run was "
                     "going (pxh removed only its own files from it)\n";
}

nlohmann::json file_records(const fs::path& dir) {
    nlohmann::json files = nlohmann::json::object();
    std::vector<fs::path> paths;
    for (const auto& e : fs::recursive_directory_iterator(dir))
        if (fs::is_regular_file(e.symlink_status()) && e.path() != dir / "run.json")
            paths.push_back(e.path());
    std::sort(paths.begin(), paths.end());
    for (const auto& p : paths)
        files[p.lexically_relative(dir).generic_string()] = {{"bytes", fs::file_size(p)},
                                                             {"sha256", sha256_file(p.string())}};
    return files;
}

std::string verify_results_folder(const std::string& dir, bool accept_edited) {
    const fs::path d(dir);
    auto refuse = [&](const std::string& where, const std::string& what) -> std::string {
        if (!accept_edited)
            throw InputError(where, what +
                                        " (refused: these are not the results a run wrote; "
                                        "pass --accept-edited to use them anyway)");
        std::cerr << "pxh: warning: " << one_line(where + ": " + what) << "\n";
        return "NOT VERIFIED (--accept-edited): " + one_line(where + ": " + what);
    };
    std::error_code ec;
    if (!fs::is_directory(d, ec)) throw InputError(dir, "no such results folder");
    // A folder an interrupted run left is never certified, whatever it holds.
    fs::path named = d.lexically_normal();
    if (named.filename().empty()) named = named.parent_path();
    const std::string leaf = named.filename().string();
    if (pid_suffix(leaf, ".partial-") > 0)
        throw InputError(dir,
                         "is the partial folder of a pxh run that did not finish (NAME"
                         ".partial-PID-...): not complete results, never verified");
    if (pid_suffix(leaf, ".replaced-") > 0)
        throw InputError(dir,
                         "is an earlier results folder that an interrupted --force run was "
                         "replacing (NAME.replaced-PID-...): rename it to a name of its own "
                         "to check it");
    const fs::path run_json = d / "run.json";
    if (!fs::exists(run_json, ec))
        return refuse(run_json.string(),
                      "missing: a complete pxh results folder has run.json "
                      "(written last by pxh run)");
    if (!fs::is_regular_file(run_json, ec))
        throw InputError(run_json.string(), "is not a regular file");
    nlohmann::json run;
    try {
        std::ifstream f(run_json, std::ios::binary);
        run = nlohmann::json::parse(f);
    } catch (const std::exception& e) {
        return refuse(run_json.string(), std::string("unreadable: ") + e.what());
    }
    if (!run.is_object() || !run.contains("files") || !run["files"].is_object() ||
        !run.contains("rows") || !run["rows"].is_number_unsigned())
        return refuse(run_json.string(), "records no file checksums (written by an older pxh?)");
    const auto& files = run["files"];
    if (!files.contains("results.csv"))
        return refuse(run_json.string(), "does not record results.csv");
    const fs::path csv = d / "results.csv";
    const size_t rows_recorded = run["rows"].get<size_t>();
    size_t checked = 0;
    for (const auto& [rel, rec] : files.items()) {
        const fs::path p = d / rel;
        if (!fs::is_regular_file(p, ec)) return refuse(p.string(), "missing (run.json records it)");
        if (!rec.is_object() || !rec.contains("sha256") || !rec["sha256"].is_string())
            return refuse(run_json.string(), "malformed record for '" + rel + "'");
        const std::string want = rec["sha256"].get<std::string>();
        if (sha256_file(p.string()) == want) {
            ++checked;
            continue;
        }
        if (p == csv) {
            // Say what differs when the table still reads.
            size_t have = 0;
            try {
                have = read_csv(csv.string()).rows.size();
            } catch (const InputError& e) {
                return refuse(csv.string(),
                              std::string("does not match run.json and is malformed: ") + e.what());
            }
            if (have < rows_recorded)
                return refuse(csv.string(), std::to_string(have) + " rows, run.json records " +
                                                std::to_string(rows_recorded) +
                                                ": rows are missing");
            if (have > rows_recorded)
                return refuse(csv.string(), std::to_string(have) + " rows, run.json records " +
                                                std::to_string(rows_recorded) +
                                                ": rows were added");
            return refuse(csv.string(),
                          "values differ from what the run wrote (sha256 mismatch, "
                          "same row count): edited?");
        }
        return refuse(p.string(), "differs from what the run wrote (sha256 mismatch)");
    }
    return "verified: " + csv.string() + " (" + std::to_string(rows_recorded) + " rows) and " +
           std::to_string(checked - 1) + " other file(s) match run.json";
}

}  // namespace pxh
