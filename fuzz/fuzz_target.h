// Fuzz targets for pxh's hostile-input surfaces (experiment files, thresholds files,
// results.csv, height images). One target per fuzz/*_fuzz.cpp, written once and built two ways:
//  - with libFuzzer (clang, -DPXH_LIBFUZZER; scripts/fuzz.sh): PXH_FUZZ_TARGET(name) is the
//    LLVMFuzzerTestOneInput of that target's own executable fuzz_NAME;
//  - in the normal build: every target registers itself under its name in pxh_fuzz_replay,
//    which feeds each file of fuzz/corpus/NAME/ to target NAME once (ctest fuzz_corpus_replay).
// A target catches pxh's expected errors (InputError and any other std::exception: bad input is
// allowed to be refused); only crashes, hangs, sanitizer reports and leaks are findings.
#pragma once
#include <cstddef>
#include <cstdint>
#include <map>
#include <string>

namespace pxh::fuzz {

using Target = int (*)(const uint8_t* data, size_t size);

// The replay runner's targets by name (filled by PXH_FUZZ_TARGET before main runs).
std::map<std::string, Target>& targets();
bool register_target(const char* name, Target fn);

// A scratch folder private to this process (created on first use, removed at exit).
const std::string& scratch_dir();

// Writes the bytes to scratch_dir()/name and returns the full path.
std::string write_scratch(const std::string& name, const uint8_t* data, size_t size);

// Sends this process's stdout to /dev/null (pxh check prints its table there); once.
void silence_stdout();

}  // namespace pxh::fuzz

#ifdef PXH_LIBFUZZER
#define PXH_FUZZ_TARGET(name) \
    extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
#else
#define PXH_FUZZ_TARGET(name)                                       \
    static int pxh_fuzz_##name(const uint8_t* data, size_t size);   \
    [[maybe_unused]] static const bool pxh_fuzz_registered_##name = \
        pxh::fuzz::register_target(#name, pxh_fuzz_##name);         \
    static int pxh_fuzz_##name(const uint8_t* data, size_t size)
#endif
