#include "harness/results/provenance.h"

#include <GL/osmesa.h>
#include <OpenImageIO/oiioversion.h>
#include <embree3/rtcore_config.h>
#include <oneapi/tbb/version.h>
#include <toml++/toml.h>
#include <unistd.h>

#include <Eigen/Core>
#include <array>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <thread>

namespace pxh {
namespace {

std::string run_command(const std::string& cmd) {
    std::array<char, 256> buf{};
    std::string out;
    if (FILE* p = popen(cmd.c_str(), "r")) {
        while (fgets(buf.data(), buf.size(), p)) out += buf.data();
        pclose(p);
    }
    while (!out.empty() && (out.back() == '\n' || out.back() == '\r')) out.pop_back();
    return out;
}

}  // namespace

std::string cpu_model() {
    std::ifstream f("/proc/cpuinfo");
    std::string line;
    while (std::getline(f, line))
        if (line.rfind("model name", 0) == 0) {
            auto pos = line.find(':');
            return pos == std::string::npos ? line : line.substr(pos + 2);
        }
    return "unknown";
}

std::string utc_timestamp(const char* fmt) {
    std::time_t t = std::time(nullptr);
    std::tm tm{};
    gmtime_r(&t, &tm);
    char buf[64];
    std::strftime(buf, sizeof buf, fmt, &tm);
    return buf;
}

std::string pxh_version() {
    const std::string src = PXH_SOURCE_DIR;
    return std::string(PXH_VERSION) + " (" +
           run_command("git -C '" + src + "' describe --always --tags --dirty 2>/dev/null") + ")";
}

nlohmann::json provenance(int threads) {
    nlohmann::json j;
    const std::string src = PXH_SOURCE_DIR;
    j["pxh_version"] = pxh_version();
    j["git_commit"] = run_command("git -C '" + src + "' rev-parse HEAD 2>/dev/null");
    j["git_dirty"] = !run_command("git -C '" + src + "' status --porcelain 2>/dev/null").empty();
    j["compiler"] = std::string("g++ ") + __VERSION__;
    j["compile_flags"] = PXH_COMPILE_FLAGS;
#ifdef NDEBUG
    j["build_type"] = "release (NDEBUG)";
#else
    j["build_type"] = "debug (asserts on)";
#endif
    j["libraries"] = {
        {"embree", RTC_VERSION_STRING},
        {"openimageio", OIIO_VERSION_STRING},
        {"eigen", std::to_string(EIGEN_WORLD_VERSION) + "." + std::to_string(EIGEN_MAJOR_VERSION) +
                      "." + std::to_string(EIGEN_MINOR_VERSION)},
        {"tbb", TBB_VERSION_STRING},
        {"tomlplusplus", std::to_string(TOML_LIB_MAJOR) + "." + std::to_string(TOML_LIB_MINOR) +
                             "." + std::to_string(TOML_LIB_PATCH)},
        {"nlohmann_json", std::to_string(NLOHMANN_JSON_VERSION_MAJOR) + "." +
                              std::to_string(NLOHMANN_JSON_VERSION_MINOR) + "." +
                              std::to_string(NLOHMANN_JSON_VERSION_PATCH)},
        {"osmesa",
         std::to_string(OSMESA_MAJOR_VERSION) + "." + std::to_string(OSMESA_MINOR_VERSION)},
    };
    char host[256] = {};
    gethostname(host, sizeof host - 1);
    j["host"] = host;
    j["cpu_model"] = cpu_model();
    j["hardware_threads"] = std::thread::hardware_concurrency();
    j["threads"] = threads;
    j["date_utc"] = utc_timestamp();
    return j;
}

}  // namespace pxh
