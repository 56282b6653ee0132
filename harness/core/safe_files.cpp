#include "harness/core/safe_files.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/random.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <iterator>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "harness/core/error.h"

namespace pxh {

namespace fs = std::filesystem;

void create_new_file(const fs::path& path, std::string_view bytes) {
    const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
    if (fd < 0) {
        const int e = errno;
        std::string why = std::strerror(e);
        if (e == EEXIST) why = "something of that name exists already (pxh writes only new files)";
        throw std::runtime_error(path.string() + ": cannot create: " + why);
    }
    const char* p = bytes.data();
    size_t left = bytes.size();
    std::string err;
    while (left > 0) {
        const ssize_t n = ::write(fd, p, left);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
            err = std::string("write failed: ") + (n < 0 ? std::strerror(errno) : "no progress");
            break;
        }
        p += n;
        left -= size_t(n);
    }
    if (err.empty() && ::fsync(fd) != 0) err = std::string("sync failed: ") + std::strerror(errno);
    if (::close(fd) != 0 && err.empty()) err = std::string("close failed: ") + std::strerror(errno);
    if (!err.empty()) {
        ::unlink(path.c_str());  // ours (created above): no partial file that looks whole
        throw std::runtime_error(path.string() + ": " + err);
    }
}

void copy_to_new_file(const fs::path& from, const fs::path& to) {
    struct stat st;
    if (::lstat(from.c_str(), &st) != 0 || !S_ISREG(st.st_mode))
        throw std::runtime_error(from.string() + ": cannot copy: not a regular file");
    std::ifstream in(from, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (!in.good() && !in.eof())
        throw std::runtime_error(from.string() + ": cannot copy: read failed");
    create_new_file(to, bytes);
}

void fsync_path(const fs::path& p, bool directory) {
    const int fd = ::open(p.c_str(), (directory ? O_RDONLY | O_DIRECTORY : O_RDONLY) | O_CLOEXEC);
    if (fd < 0)
        throw std::runtime_error(p.string() + ": cannot open to sync: " + std::strerror(errno));
    const int rc = ::fsync(fd);
    const std::string err = rc != 0 ? std::strerror(errno) : "";
    if (::close(fd) != 0 || rc != 0)
        throw std::runtime_error(p.string() + ": sync failed: " +
                                 (err.empty() ? std::string(std::strerror(errno)) : err));
}

void sync_tree(const fs::path& dir) {
    for (const auto& e : fs::recursive_directory_iterator(dir)) {
        if (e.is_symlink()) continue;
        if (e.is_directory()) fsync_path(e.path(), true);
        else if (e.is_regular_file()) fsync_path(e.path(), false);
    }
    fsync_path(dir, true);
}

void make_own_folder(const fs::path& path) {
    if (::mkdir(path.c_str(), 0777) == 0) return;
    const int e = errno;
    struct stat st;
    if (e == EEXIST && ::lstat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode)) return;
    throw std::runtime_error(path.string() + ": cannot create the folder: " +
                             (e == EEXIST ? std::string("something that is not a folder (a link?) "
                                                        "has that name")
                                          : std::string(std::strerror(e))));
}

std::string random_hex8() {
    unsigned char b[4] = {0, 0, 0, 0};
    size_t got = 0;
    while (got < sizeof b) {
        const ssize_t n = ::getrandom(b + got, sizeof b - got, 0);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) throw std::runtime_error(std::string("getrandom: ") + std::strerror(errno));
        got += size_t(n);
    }
    char out[9];
    std::snprintf(out, sizeof out, "%02x%02x%02x%02x", b[0], b[1], b[2], b[3]);
    return out;
}

fs::path make_unique_folder(const std::string& base) {
    for (int attempt = 0; attempt < 100; ++attempt) {
        const fs::path p = base + "-" + random_hex8();
        if (::mkdir(p.c_str(), 0777) == 0) return p;
        if (errno != EEXIST)
            throw std::runtime_error(p.string() +
                                     ": cannot create the folder: " + std::strerror(errno));
    }
    throw std::runtime_error(base + "-*: cannot create a folder of a new name (100 tries)");
}

fs::path move_aside(const fs::path& path, const std::string& kind) {
    for (int attempt = 0; attempt < 100; ++attempt) {
        const fs::path a =
            path.string() + "." + kind + "-" + std::to_string(::getpid()) + "-" + random_hex8();
        if (::renameat2(AT_FDCWD, path.c_str(), AT_FDCWD, a.c_str(), RENAME_NOREPLACE) == 0)
            return a;
        if (errno != EEXIST)
            throw std::runtime_error("cannot move " + path.string() +
                                     " aside: " + std::strerror(errno));
    }
    throw std::runtime_error("cannot move " + path.string() + " aside (100 names taken)");
}

void replace_own_file(const fs::path& path, std::string_view text,
                      const std::function<bool(const fs::path&)>& ours, const std::string& where,
                      const std::string& not_ours) {
    // Whether `path` exists, refused unless it is a regular file `ours` accepts.
    auto existing = [&] {
        struct stat st {};
        if (::lstat(path.c_str(), &st) != 0) return false;
        if (S_ISLNK(st.st_mode))
            throw InputError(where, path.string() + " is a symbolic link: not replaced");
        if (!S_ISREG(st.st_mode))
            throw InputError(where,
                             path.string() + " exists and is not a regular file: not replaced");
        if (!ours(path)) throw InputError(where, not_ours);
        return true;
    };
    existing();
    const fs::path tmp =
        path.string() + ".partial-" + std::to_string(::getpid()) + "-" + random_hex8();
    create_new_file(tmp, text);
    int rc = 0;
    try {
        rc = existing()
                 ? ::rename(tmp.c_str(), path.c_str())
                 : ::renameat2(AT_FDCWD, tmp.c_str(), AT_FDCWD, path.c_str(), RENAME_NOREPLACE);
    } catch (...) {
        ::unlink(tmp.c_str());
        throw;
    }
    if (rc != 0) {
        const std::string why = std::strerror(errno);
        ::unlink(tmp.c_str());
        throw std::runtime_error(path.string() + ": cannot put the file in place: " + why);
    }
}

// ---- OwnedFolder ----

const char* const OwnedFolder::kManifest = "manifest.txt";

namespace {

std::string sys_error(const fs::path& p, const std::string& what, int e) {
    return p.string() + ": " + what + ": " + std::strerror(e);
}

// A manifest entry: a relative path of plain characters below DIR (no "..", no empty part);
// "a/" a folder, "a/**" a staging folder.
bool own_name(std::string rel) {
    if (rel.size() > 3 && rel.compare(rel.size() - 3, 3, "/**") == 0) rel.resize(rel.size() - 2);
    if (rel.empty() || rel.front() == '/' || rel == OwnedFolder::kManifest) return false;
    for (char c : rel)
        if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' || c == '-' ||
              c == '/' || static_cast<unsigned char>(c) >= 0x80))
            return false;
    std::stringstream ss(rel.back() == '/' ? rel.substr(0, rel.size() - 1) : rel);
    for (std::string part; std::getline(ss, part, '/');)
        if (part.empty() || part == "." || part == "..") return false;
    return true;
}

bool write_all(int fd, std::string_view text) {
    size_t done = 0;
    while (done < text.size()) {
        const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return false;
        done += size_t(n);
    }
    return true;
}

// Removes a staging folder whole: regular files and folders only (a link or another kind of
// file in it is left, with a warning, and so are the folders holding it).
void remove_staging(const fs::path& dir) {
    std::error_code ec;
    std::vector<fs::path> folders{dir};
    for (auto it = fs::recursive_directory_iterator(dir, ec);
         !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
        const auto st = it->symlink_status();
        if (fs::is_directory(st)) folders.push_back(it->path());
        else if (fs::is_regular_file(st)) ::unlink(it->path().c_str());
        else
            std::cerr << "pxh: warning: " << it->path().string()
                      << ": not a file pxh wrote (a link or another kind): left alone\n";
    }
    std::sort(folders.begin(), folders.end(), [](const fs::path& a, const fs::path& b) {
        return a.native().size() > b.native().size();  // deepest first
    });
    for (const auto& f : folders) ::rmdir(f.c_str());
}

}  // namespace

std::set<std::string> OwnedFolder::listed(const fs::path& dir) {
    std::set<std::string> out;
    const fs::path m = dir / kManifest;
    struct stat st {};
    if (::lstat(m.c_str(), &st) != 0) return out;
    if (!S_ISREG(st.st_mode))
        throw InputError(m.string(),
                         "is not a regular file (a link?), so not pxh's list of its "
                         "files there; remove it");
    std::ifstream f(m, std::ios::binary);
    for (std::string rel; std::getline(f, rel);)
        if (!rel.empty() && rel[0] != '#') out.insert(rel);
    return out;
}

OwnedFolder OwnedFolder::open(const fs::path& dir, const std::string& owner) {
    struct stat st {};
    if (::lstat(dir.c_str(), &st) == 0) {
        if (S_ISLNK(st.st_mode))
            throw InputError(dir.string(), "is a symbolic link; " + owner +
                                               " writes only into a folder of its own (remove "
                                               "the link)");
        if (!S_ISDIR(st.st_mode)) throw InputError(dir.string(), "exists and is not a folder");
    } else if (errno != ENOENT || ::mkdir(dir.c_str(), 0755) != 0) {
        throw std::runtime_error(sys_error(dir, "cannot make the folder", errno));
    }
    const fs::path m = dir / kManifest;
    std::vector<std::string> dirs;
    for (const std::string& rel : listed(dir)) {
        if (!own_name(rel)) {
            std::cerr << "pxh: warning: " << m.string() << ": '" << one_line(rel)
                      << "' is not a name " << owner << " writes: left alone\n";
            continue;
        }
        const bool staged = rel.size() > 3 && rel.compare(rel.size() - 3, 3, "/**") == 0;
        const fs::path p = dir / (staged ? rel.substr(0, rel.size() - 3) : rel);
        struct stat ps {};
        if (::lstat(p.c_str(), &ps) != 0) continue;  // already gone
        if (staged && S_ISDIR(ps.st_mode)) {
            remove_staging(p);
        } else if (rel.back() == '/' && S_ISDIR(ps.st_mode)) {
            dirs.push_back(rel);
        } else if (rel.back() != '/' && !staged && S_ISREG(ps.st_mode)) {
            if (::unlink(p.c_str()) != 0)
                throw std::runtime_error(sys_error(p, "cannot remove", errno));
        } else {
            std::cerr << "pxh: warning: " << p.string() << ": not the file " << owner
                      << " wrote there (a link or another kind of file now): left alone\n";
        }
    }
    std::sort(dirs.rbegin(), dirs.rend());  // deepest first
    for (const auto& rel : dirs)
        if (::rmdir((dir / rel).c_str()) != 0 && errno != ENOENT)
            std::cerr << "pxh: warning: " << (dir / rel).string() << ": holds files " << owner
                      << " did not write: left as it is\n";
    if (::unlink(m.c_str()) != 0 && errno != ENOENT)
        throw std::runtime_error(sys_error(m, "cannot remove", errno));
    const int fd = ::open(m.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
    if (fd < 0) throw std::runtime_error(sys_error(m, "cannot create", errno));
    const bool wrote =
        write_all(fd, "# The files " + owner + " wrote in this folder, one a line: the next " +
                          owner + " removes exactly these, and nothing else.\n");
    const int e = errno;
    if (::close(fd) != 0 || !wrote) throw std::runtime_error(sys_error(m, "cannot write", e));
    std::cout << "wrote " << m.string() << "\n";
    return OwnedFolder(dir, owner);
}

void OwnedFolder::record(const std::string& rel) const {
    const fs::path m = dir_ / kManifest;
    const int fd = ::open(m.c_str(), O_WRONLY | O_APPEND | O_NOFOLLOW | O_CLOEXEC);
    if (fd < 0) throw std::runtime_error(sys_error(m, "cannot open", errno));
    const bool wrote = write_all(fd, rel + "\n");
    const int e = errno;
    if (::close(fd) != 0 || !wrote) throw std::runtime_error(sys_error(m, "cannot write", e));
}

void OwnedFolder::folder(const std::string& rel) const {
    const fs::path p = dir_ / rel;
    struct stat st {};
    if (::lstat(p.c_str(), &st) == 0) {
        if (!S_ISDIR(st.st_mode))
            throw InputError(p.string(), S_ISLNK(st.st_mode)
                                             ? "is a symbolic link; " + owner_ +
                                                   " writes only into folders of its own "
                                                   "(remove the link)"
                                             : std::string("exists and is not a folder"));
        return;  // left from before with someone else's files in it: ours to write into
    }
    if (::mkdir(p.c_str(), 0755) != 0)
        throw std::runtime_error(sys_error(p, "cannot make the folder", errno));
    record(rel + "/");
}

namespace {

// Links `tmp` (ours) to `p`, never over a name that exists; falls back to rename where the
// file system has no hard links. Returns errno, 0 on success (tmp then gone).
int link_new(const fs::path& tmp, const fs::path& p) {
    if (::link(tmp.c_str(), p.c_str()) == 0) {
        ::unlink(tmp.c_str());
        return 0;
    }
    const int e = errno;
    struct stat st {};
    if (::lstat(p.c_str(), &st) == 0) return EEXIST;
    if ((e == EPERM || e == ENOTSUP || e == EXDEV || e == EMLINK) &&
        ::renameat2(AT_FDCWD, tmp.c_str(), AT_FDCWD, p.c_str(), RENAME_NOREPLACE) == 0)
        return 0;
    return e;
}

}  // namespace

void OwnedFolder::write(const std::string& rel, std::string_view text) const {
    const fs::path p = dir_ / rel;
    const fs::path tmp =
        p.parent_path() / ("." + p.filename().string() + ".tmp-" + std::to_string(::getpid()));
    const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
    if (fd < 0) throw std::runtime_error(sys_error(tmp, "cannot create", errno));
    record((fs::path(rel).parent_path() / tmp.filename()).string());
    bool ok = write_all(fd, text);
    int e = ok ? 0 : errno;
    if (::close(fd) != 0 && ok) {
        ok = false;
        e = errno;
    }
    if (ok) e = link_new(tmp, p);
    if (!ok || e != 0) {
        ::unlink(tmp.c_str());
        if (e == EEXIST)
            throw InputError(p.string(),
                             "exists and " + owner_ + " did not write it (it is not in " +
                                 (dir_ / kManifest).string() + "); move it away or remove it");
        throw std::runtime_error(sys_error(p, "cannot write", e));
    }
    record(rel);
    std::cout << "wrote " << p.string() << "\n";
}

fs::path OwnedFolder::staging() const {
    const fs::path s = make_unique_folder((dir_ / ".staging").string());
    record(s.filename().string() + "/**");
    return s;
}

void OwnedFolder::adopt(const fs::path& staging) const {
    std::vector<fs::path> files;
    for (auto it = fs::recursive_directory_iterator(staging);
         it != fs::recursive_directory_iterator(); ++it) {
        const auto st = it->symlink_status();
        const fs::path rel = it->path().lexically_relative(staging);
        if (fs::is_directory(st)) folder(rel.generic_string());
        else if (fs::is_regular_file(st)) files.push_back(rel);
        else
            throw std::runtime_error(it->path().string() +
                                     ": not a regular file; nothing in it is taken");
    }
    std::sort(files.begin(), files.end());
    const auto taken = [&](const fs::path& p) {
        return InputError(p.string(), "exists and " + owner_ + " did not write it (it is not in " +
                                          (dir_ / kManifest).string() +
                                          "); move it away or remove it");
    };
    for (const auto& rel : files) {  // all or none: every name checked before any is taken
        struct stat st {};
        if (::lstat((dir_ / rel).c_str(), &st) == 0) throw taken(dir_ / rel);
    }
    for (const auto& rel : files) {
        const fs::path p = dir_ / rel;
        const int e = link_new(staging / rel, p);
        if (e == EEXIST) throw taken(p);
        if (e != 0) throw std::runtime_error(sys_error(p, "cannot write", e));
        record(rel.generic_string());
        std::cout << "wrote " << p.string() << "\n";
    }
    remove_staging(staging);
}

void OwnedFolder::discard(const fs::path& staging) const { remove_staging(staging); }

void ignore_write_signals() {
    ::signal(SIGPIPE, SIG_IGN);
    ::signal(SIGXFSZ, SIG_IGN);
}

size_t invalid_utf8_at(std::string_view s) {
    const auto* p = reinterpret_cast<const unsigned char*>(s.data());
    const size_t n = s.size();
    size_t i = 0;
    while (i < n) {
        const unsigned c = p[i];
        if (c < 0x80) {
            ++i;
            continue;
        }
        size_t len = 0;
        unsigned lo = 0x80, hi = 0xBF;  // the allowed range of the second byte
        if (c >= 0xC2 && c <= 0xDF) len = 2;
        else if (c >= 0xE0 && c <= 0xEF) {
            len = 3;
            if (c == 0xE0) lo = 0xA0;  // overlong
            if (c == 0xED) hi = 0x9F;  // surrogates
        } else if (c >= 0xF0 && c <= 0xF4) {
            len = 4;
            if (c == 0xF0) lo = 0x90;  // overlong
            if (c == 0xF4) hi = 0x8F;  // past U+10FFFF
        } else {
            return i;  // a continuation byte, 0xC0/0xC1 or 0xF5..0xFF where a character starts
        }
        if (i + len > n) return i;
        if (p[i + 1] < lo || p[i + 1] > hi) return i;
        for (size_t k = 2; k < len; ++k)
            if (p[i + k] < 0x80 || p[i + k] > 0xBF) return i;
        i += len;
    }
    return std::string_view::npos;
}

std::string utf8_problem(std::string_view text) {
    const size_t at = invalid_utf8_at(text);
    if (at == std::string_view::npos) return "";
    size_t line = 1, line_start = 0;
    for (size_t k = 0; k < at; ++k)
        if (text[k] == '\n') ++line, line_start = k + 1;
    char hex[8];
    std::snprintf(hex, sizeof hex, "0x%02X", unsigned((unsigned char)text[at]));
    return "line " + std::to_string(line) + ", column " + std::to_string(at - line_start + 1) +
           ": byte " + hex + " is not UTF-8";
}

}  // namespace pxh
