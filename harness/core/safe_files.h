// Files and folders pxh creates, created safely: the one home of safe writing (the results
// folder, run.json, merge, the report folder and its plot script, the verdict files and the
// commands write through these; harness/report/plot_report.py only creates new files in a
// folder made here for it). Never through a symbolic link and never over something that exists
// (open with O_CREAT | O_EXCL | O_NOFOLLOW, mkdir that fails on an existing name), every write,
// fsync and close checked. What pxh writes is then its own: a name someone else prepared (a link, a
// file, a folder) makes the write fail, it is not adopted.
#pragma once
#include <filesystem>
#include <functional>
#include <set>
#include <string>
#include <string_view>

namespace pxh {

// Creates `path`, which must not exist (a file, a link, anything there is an error), writes
// `bytes`, fsyncs and closes it. Throws std::runtime_error "PATH: cannot create: REASON" or
// "PATH: write failed: REASON" (a full disk, a file-size limit); a file that could not be
// written whole is removed again.
void create_new_file(const std::filesystem::path& path, std::string_view bytes);

// Copies the regular file `from` (not a link) into `to` as create_new_file writes it.
void copy_to_new_file(const std::filesystem::path& from, const std::filesystem::path& to);

// fsyncs a file or (directory) a folder; std::runtime_error naming the path when it fails.
void fsync_path(const std::filesystem::path& path, bool directory);
// fsyncs every regular file and folder under (and including) `dir` (links are skipped).
void sync_tree(const std::filesystem::path& dir);

// A folder inside one of pxh's own folders: created with mkdir, or, when it exists already, it
// must be a real folder (not a link to one). Throws std::runtime_error naming the path.
void make_own_folder(const std::filesystem::path& path);

// Creates a new folder "BASE-SUFFIX" beside BASE with mkdir (never one that exists: the suffix
// is random and mkdir fails on an existing name, so another is tried) and returns its path.
std::filesystem::path make_unique_folder(const std::string& base);

// Moves `path` aside to a new name "PATH.KIND-PID-HEX" beside it (renameat2 with
// RENAME_NOREPLACE: nothing is replaced) and returns that name; std::runtime_error when it
// cannot.
std::filesystem::path move_aside(const std::filesystem::path& path, const std::string& kind);

// Writes `path` whole or not at all, through a new temporary file beside it (create_new_file)
// renamed into place: a `path` that exists must be a regular file (not a link) that `ours`
// accepts (checked again just before the rename), else InputError(where, not_ours) and nothing
// is touched; a `path` that does not exist is created (never over a name that appeared
// meanwhile). std::runtime_error when the write fails.
void replace_own_file(const std::filesystem::path& path, std::string_view text,
                      const std::function<bool(const std::filesystem::path&)>& ours,
                      const std::string& where, const std::string& not_ours);

// A folder pxh shares with its user, owned file by file (RESULTS/report/, pxh report's):
// DIR/manifest.txt lists every file and folder `owner` created there, one a line, relative to
// DIR ("a/b.png", folders "a/", a staging folder "NAME/**"). open() refuses a DIR (or
// manifest) that is a symbolic link or not a folder, removes exactly the entries of the
// previous manifest (a regular file or empty folder of that name, a staging folder whole;
// anything else is left alone, with a warning) and starts a new manifest. write() goes through
// a temporary name created exclusively (O_EXCL | O_NOFOLLOW) and links it to its name, which
// must not exist (a file the owner did not write is never replaced: InputError "PATH: exists and
// OWNER did not write it"); a failed write (a full disk, a file-size limit) removes the
// temporary file and throws, so no name ever holds a truncated file.
class OwnedFolder {
  public:
    static const char* const kManifest;  // "manifest.txt"
    OwnedFolder(std::filesystem::path dir, std::string owner)
        : dir_(std::move(dir)), owner_(std::move(owner)) {}
    static OwnedFolder open(const std::filesystem::path& dir, const std::string& owner);
    const std::filesystem::path& dir() const { return dir_; }

    void folder(const std::string& rel) const;  // makes DIR/rel (kept when it is a real folder)
    void write(const std::string& rel, std::string_view text) const;
    // A folder of a new name in DIR for another process (the plot script) to create files in;
    // recorded as "NAME/**", so a later open() removes it whole even after a crash.
    std::filesystem::path staging() const;
    // Moves every regular file below `staging` to the same relative name in DIR (link(),
    // never over a name that exists), records each, prints "wrote PATH", removes `staging`.
    // A link or other kind of file in it: std::runtime_error.
    void adopt(const std::filesystem::path& staging) const;
    // Removes `staging` and what is in it (after a failed drawing).
    void discard(const std::filesystem::path& staging) const;

    // The entries DIR/manifest.txt lists (empty when there is none); InputError when the
    // manifest is not a regular file.
    static std::set<std::string> listed(const std::filesystem::path& dir);

  private:
    void record(const std::string& rel) const;
    std::filesystem::path dir_;
    std::string owner_;
};

// 8 random hex digits (from the kernel's random source).
std::string random_hex8();

// SIGPIPE and SIGXFSZ ignored: a write to a closed pipe or past a file-size limit then fails
// (EPIPE, EFBIG) and is reported like any other write error, instead of ending the process
// without a word (and without the clean-up of a partial results folder).
void ignore_write_signals();

// The offset of the first byte of `text` that is not part of well-formed UTF-8 (overlong
// forms, surrogates and code points past U+10FFFF are not), or std::string::npos.
size_t invalid_utf8_at(std::string_view text);

// "" when `text` is well-formed UTF-8; else one line naming where: "line L, column C: byte 0xNN
// is not UTF-8" (lines and columns counted in bytes from 1).
std::string utf8_problem(std::string_view text);

}  // namespace pxh
