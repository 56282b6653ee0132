#include "harness/core/safe_files.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/random.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <stdexcept>

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
