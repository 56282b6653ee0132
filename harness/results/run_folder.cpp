#include "harness/results/run_folder.h"

#include <dirent.h>
#include <fcntl.h>
#include <pthread.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <iostream>
#include <mutex>
#include <set>
#include <sstream>
#include <thread>

#include "harness/core/error.h"
#include "harness/core/sha256.h"
#include "harness/results/csv_table.h"

namespace pxh {
namespace {

namespace fs = std::filesystem;

// What a run (and pxh report) writes into a results folder: the only entries --force removes.
const std::set<std::string> kPxhEntries = {"results.csv", "run.json", "maps", "pictures", "report"};

std::string errno_text() { return std::strerror(errno); }

// Signal clean-up: SIGINT/SIGTERM/SIGHUP are blocked in every thread (the mask is inherited
// by TBB's and llvmpipe's workers, created later) and taken by one thread with sigwait, which
// runs in normal context, so it may remove the partial folder. `mu` orders it against commit.
struct SignalState {
    std::mutex mu;
    fs::path tmp, lock_path;
    bool active = false, committed = false;
};
SignalState& signal_state() {
    static SignalState s;
    return s;
}

void install_signal_cleanup() {
    static std::once_flag once;
    std::call_once(once, [] {
        sigset_t set;
        sigemptyset(&set);
        sigaddset(&set, SIGINT);
        sigaddset(&set, SIGTERM);
        sigaddset(&set, SIGHUP);
        pthread_sigmask(SIG_BLOCK, &set, nullptr);
        std::thread([set] {
            int sig = 0;
            sigwait(&set, &sig);
            SignalState& s = signal_state();
            std::lock_guard<std::mutex> lock(s.mu);
            if (s.active && !s.committed) {
                std::error_code ec;
                fs::remove_all(s.tmp, ec);
                fs::remove(s.lock_path, ec);
                std::cerr << "\npxh: interrupted (signal " << sig << "); removed " << s.tmp.string()
                          << ", no results written\n";
            }
            _exit(128 + sig);
        }).detach();
    });
}

void fsync_path(const fs::path& p, bool directory) {
    const int fd = ::open(p.c_str(), (directory ? O_RDONLY | O_DIRECTORY : O_RDONLY) | O_CLOEXEC);
    if (fd < 0) throw std::runtime_error(p.string() + ": cannot open to sync: " + errno_text());
    const int rc = ::fsync(fd);
    const std::string err = rc != 0 ? errno_text() : "";
    if (::close(fd) != 0 || rc != 0)
        throw std::runtime_error(p.string() +
                                 ": sync failed: " + (err.empty() ? errno_text() : err));
}

// fsync every regular file and folder under (and including) dir.
void sync_tree(const fs::path& dir) {
    for (const auto& e : fs::recursive_directory_iterator(dir)) {
        if (e.is_symlink()) continue;
        if (e.is_directory()) fsync_path(e.path(), true);
        else if (e.is_regular_file()) fsync_path(e.path(), false);
    }
    fsync_path(dir, true);
}

// pid of a NAME.partial-PID / NAME.replaced-PID folder, or -1.
long pid_suffix(const std::string& name, const std::string& kind) {
    const size_t at = name.rfind(kind);
    if (at == std::string::npos || at == 0 || at + kind.size() == name.size()) return -1;
    const std::string digits = name.substr(at + kind.size());
    if (digits.find_first_not_of("0123456789") != std::string::npos || digits.size() > 9) return -1;
    return std::stol(digits);
}

// Names the folders beside final_dir that interrupted runs left (their process is gone).
void warn_stale_siblings(const fs::path& final_dir) {
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(final_dir.parent_path(), ec)) {
        if (!e.is_directory(ec)) continue;
        const std::string name = e.path().filename().string();
        for (const std::string kind : {".partial-", ".replaced-"}) {
            const long pid = pid_suffix(name, kind);
            if (pid <= 0 || pid == long(getpid())) continue;
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

// The entries of an existing results folder that --force would remove, after checking that
// there is nothing else in it.
void check_replaceable(const fs::path& dir) {
    for (const auto& e : fs::directory_iterator(dir)) {
        const std::string name = e.path().filename().string();
        if (!kPxhEntries.count(name))
            throw InputError(dir.string(), "--force would delete '" + name +
                                               "', which pxh did not write there; move it away "
                                               "or choose another --out");
    }
}

}  // namespace

void write_file_synced(const fs::path& path, const std::string& text) {
    const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0) throw std::runtime_error(path.string() + ": cannot create: " + errno_text());
    const char* p = text.data();
    size_t left = text.size();
    std::string err;
    while (left > 0 && err.empty()) {
        const ssize_t n = ::write(fd, p, left);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
            err = "write failed: " + errno_text();
            break;
        }
        p += n;
        left -= size_t(n);
    }
    if (err.empty() && ::fsync(fd) != 0) err = "sync failed: " + errno_text();
    if (::close(fd) != 0 && err.empty()) err = "close failed: " + errno_text();
    if (!err.empty()) throw std::runtime_error(path.string() + ": " + err);
}

RunFolder::RunFolder(const std::string& out, bool force) {
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

    // One writer per DIR: an advisory lock on PARENT/.NAME.pxh-lock (freed if we die).
    lock_path_ = final_.parent_path() / ("." + final_.filename().string() + ".pxh-lock");
    lock_fd_ = ::open(lock_path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (lock_fd_ < 0)
        throw InputError(lock_path_.string(), "cannot create the lock file: " + errno_text());
    if (::flock(lock_fd_, LOCK_EX | LOCK_NB) != 0) {
        ::close(lock_fd_);
        lock_fd_ = -1;
        throw InputError(out, "another pxh run is writing this folder now (it holds " +
                                  lock_path_.string() + "); wait for it or choose another --out");
    }
    if (fs::is_directory(final_) && !fs::is_empty(final_)) {
        if (!fs::exists(final_ / "run.json"))
            throw InputError(out,
                             "exists, is not empty and is not a pxh results folder (no "
                             "run.json); pxh never deletes what it did not create: choose "
                             "another --out");
        if (!force)
            throw InputError(out,
                             "holds earlier pxh results (run.json); pass --force to replace "
                             "them, or choose another --out");
        check_replaceable(final_);
        replace_ = true;
    }
    warn_stale_siblings(final_);

    install_signal_cleanup();
    tmp_ = final_.string() + ".partial-" + std::to_string(getpid());
    {
        SignalState& s = signal_state();
        std::lock_guard<std::mutex> lock(s.mu);
        s.tmp = tmp_;
        s.lock_path = lock_path_;
        s.active = true;
        s.committed = false;
    }
    fs::create_directory(tmp_);
}

RunFolder::~RunFolder() {
    SignalState& s = signal_state();
    std::lock_guard<std::mutex> lock(s.mu);
    std::error_code ec;
    if (s.active && !s.committed) fs::remove_all(tmp_, ec);
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
    if (replace_) {
        check_replaceable(final_);  // still only pxh's files (checked again: time has passed)
        aside = final_.string() + ".replaced-" + std::to_string(getpid());
        fs::rename(final_, aside);
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
    if (!aside.empty()) {
        // Only what pxh wrote was there (checked above); delete it, then the empty folder.
        for (const auto& name : kPxhEntries) fs::remove_all(aside / name);
        fs::remove(aside);
    }
}

nlohmann::json file_records(const fs::path& dir) {
    nlohmann::json files = nlohmann::json::object();
    std::vector<fs::path> paths;
    for (const auto& e : fs::recursive_directory_iterator(dir))
        if (e.is_regular_file() && e.path() != dir / "run.json") paths.push_back(e.path());
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
