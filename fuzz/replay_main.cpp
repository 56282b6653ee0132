// pxh_fuzz_replay: the fuzz targets without libFuzzer, for the normal build and ctest.
//   pxh_fuzz_replay CORPUS_ROOT          feeds every file of CORPUS_ROOT/NAME/ to target NAME,
//                                        for every target (each must have a non-empty folder)
//   pxh_fuzz_replay TARGET FILE...       feeds the given files to one target (reproduce a crash)
// A crash or sanitizer report ends the process; otherwise it prints one line per target and
// exits 0. Exit status 2: usage error or a missing corpus.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "fuzz/fuzz_target.h"

namespace fs = std::filesystem;

namespace {

void feed(pxh::fuzz::Target target, const fs::path& file) {
    std::ifstream f(file, std::ios::binary);
    const std::vector<char> bytes((std::istreambuf_iterator<char>(f)),
                                  std::istreambuf_iterator<char>());
    target(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size());
}

}  // namespace

int main(int argc, char** argv) {
    const auto& targets = pxh::fuzz::targets();
    if (argc == 2) {
        int failed = 0;
        for (const auto& [name, target] : targets) {
            const fs::path dir = fs::path(argv[1]) / name;
            std::vector<fs::path> files;
            std::error_code ec;
            for (const auto& e : fs::directory_iterator(dir, ec))
                if (e.is_regular_file()) files.push_back(e.path());
            if (files.empty()) {
                std::fprintf(stderr, "pxh_fuzz_replay: no corpus files in %s\n", dir.c_str());
                ++failed;
                continue;
            }
            std::sort(files.begin(), files.end());  // a fixed order
            for (const auto& f : files) feed(target, f);
            std::fprintf(stderr, "%s: %zu inputs, no crash\n", name.c_str(), files.size());
        }
        return failed ? 2 : 0;
    }
    if (argc >= 3 && targets.count(argv[1])) {
        for (int i = 2; i < argc; ++i) {
            if (!fs::is_regular_file(argv[i])) {
                std::fprintf(stderr, "pxh_fuzz_replay: %s: no such file\n", argv[i]);
                return 2;
            }
            feed(targets.at(argv[1]), argv[i]);
        }
        std::fprintf(stderr, "%s: %d inputs, no crash\n", argv[1], argc - 2);
        return 0;
    }
    std::string names;
    for (const auto& [name, target] : targets) names += (names.empty() ? "" : " | ") + name;
    std::fprintf(stderr, "usage: pxh_fuzz_replay CORPUS_ROOT | pxh_fuzz_replay (%s) FILE...\n",
                 names.c_str());
    return 2;
}
