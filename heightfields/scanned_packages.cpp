// `pxh import`'s Debian packages: each one downloaded and unpacked into the cache once, and
// the licences its copyright file names.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "heightfields/scan_convert.h"

namespace pxh::scan {
namespace {

namespace fs = std::filesystem;

std::string shell(const std::string& cmd) {
    std::string out;
    if (FILE* p = popen(cmd.c_str(), "r")) {
        char buf[512];
        while (fgets(buf, sizeof buf, p)) out += buf;
        pclose(p);
    }
    while (!out.empty() && (out.back() == '\n' || out.back() == ' ')) out.pop_back();
    return out;
}

// A Debian package's files: unpacked into the cache with apt-get download + dpkg-deb -x (the
// same .deb the machine would install, without installing it); with `members`, only those
// paths ("./usr/...") are unpacked (opencv-doc is 95 MB for one 300 kB image).
std::string download_deb(const std::string& name, const fs::path& dir) {
    const std::string dl =
        "cd '" + dir.string() + "' && apt-get download -q " + name + " >/dev/null 2>&1";
    if (std::system(dl.c_str()) != 0) {
        // Package lists may be missing on a fresh machine: update once, then retry.
        std::system("apt-get update -qq >/dev/null 2>&1");
        if (std::system(dl.c_str()) != 0)
            throw std::runtime_error("apt-get download " + name +
                                     " failed (is Debian's apt reachable?)");
    }
    std::string deb;
    for (const auto& e : fs::directory_iterator(dir))
        if (e.path().extension() == ".deb") deb = e.path().string();
    if (deb.empty()) throw std::runtime_error("no .deb for " + name + " in " + dir.string());
    return deb;
}

}  // namespace

Package fetch_package(const std::string& name, const std::string& cache,
                      const std::vector<std::string>& members) {
    const fs::path dir = fs::path(cache) / name;
    const fs::path stamp = dir / ".version";
    if (fs::exists(stamp)) {
        std::ifstream f(stamp);
        std::string v;
        std::getline(f, v);
        return {name, v, (dir / "root").string()};
    }
    fs::create_directories(dir);
    const std::string deb = download_deb(name, dir);
    const std::string root = (dir / "root").string();
    std::string x = "dpkg-deb -x '" + deb + "' '" + root + "'";
    if (!members.empty()) {
        fs::create_directories(root);
        x = "dpkg-deb --fsys-tarfile '" + deb + "' | tar -x -C '" + root + "'";
        for (const auto& m : members) x += " '" + m + "'";
    }
    if (std::system(x.c_str()) != 0) throw std::runtime_error("unpacking " + deb + " failed");
    const std::string version = shell("dpkg-deb -f '" + deb + "' Version");
    std::ofstream(stamp) << version << "\n";
    fs::remove(deb);
    return {name, version, root};
}

std::vector<std::string> licences(const std::string& copyright) {
    std::ifstream f(copyright);
    std::vector<std::string> out;
    for (std::string line; std::getline(f, line);)
        if (line.rfind("License:", 0) == 0) {
            std::string l = line.substr(8);
            l.erase(0, l.find_first_not_of(' '));
            if (!l.empty() && std::find(out.begin(), out.end(), l) == out.end()) out.push_back(l);
        }
    if (out.empty()) {
        // Not machine-readable: record the licences its text names.
        std::ifstream g(copyright);
        std::stringstream ss;
        ss << g.rdbuf();
        const std::string text = ss.str();
        for (const char* name : {"GNU General Public License", "GNU Lesser General Public License",
                                 "Boost Software License"})
            if (text.find(name) != std::string::npos)
                out.push_back(std::string("mentions: ") + name);
        if (out.empty()) out.push_back("no licence named (read the copyright file)");
    }
    return out;
}

}  // namespace pxh::scan
