#include <fcntl.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "fuzz/fuzz_target.h"

namespace pxh::fuzz {

namespace fs = std::filesystem;

std::map<std::string, Target>& targets() {
    static std::map<std::string, Target> t;
    return t;
}

bool register_target(const char* name, Target fn) {
    targets()[name] = fn;
    return true;
}

namespace {
std::string g_scratch;  // set once by scratch_dir(), removed by remove_scratch at exit
void remove_scratch() {
    std::error_code ec;
    if (!g_scratch.empty()) fs::remove_all(g_scratch, ec);
}
}  // namespace

const std::string& scratch_dir() {
    if (g_scratch.empty()) {
        const fs::path dir = fs::temp_directory_path() / ("pxh_fuzz_" + std::to_string(::getpid()));
        fs::create_directories(dir);
        g_scratch = dir.string();
        std::atexit(remove_scratch);
    }
    return g_scratch;
}

std::string write_scratch(const std::string& name, const uint8_t* data, size_t size) {
    const std::string path = (fs::path(scratch_dir()) / name).string();
    std::ofstream f(path, std::ios::binary | std::ios::trunc);
    f.write(reinterpret_cast<const char*>(data), std::streamsize(size));
    f.close();
    if (!f) throw std::runtime_error("fuzz: cannot write " + path);  // the harness, not pxh
    return path;
}

void silence_stdout() {
    static const bool done = [] {
        std::fflush(stdout);
        const int null = open("/dev/null", O_WRONLY);
        if (null >= 0) {
            dup2(null, STDOUT_FILENO);
            close(null);
        }
        return true;
    }();
    (void)done;
}

}  // namespace pxh::fuzz
