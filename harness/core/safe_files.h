// Files and folders pxh creates, created safely (the one home of safe writing: the results
// folder, run.json, merge and the commands write through these): never through a symbolic link and
// never over something that exists (open with O_CREAT | O_EXCL | O_NOFOLLOW, mkdir that fails on an
// existing name), every write, fsync and close checked. What pxh writes is then its own: a
// name someone else prepared (a link, a file, a folder) makes the write fail, it is not adopted.
#pragma once
#include <filesystem>
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
