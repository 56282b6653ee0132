// The GL process (harness/backends/gl_worker.h) is pxh's binary started afresh in its worker
// mode, not a fork of the process that asked for it: a fork alone inherits every lock another
// thread held at that moment (under ASan, its allocator's: the child then waited forever for
// its context), while an exec'd pxh starts with none. And the worker mode refuses an fd that is
// not open with one line.
#include "harness/backends/gl_worker.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "tests/cli_util.h"

namespace fs = std::filesystem;

namespace {

// pxh_tests is not pxh: its GL processes are pxh's binary (pxh's own main() names itself).
const bool kWorkerProgramSet = (pxh::set_gl_worker_program(PXH_BINARY), true);

std::string read_all(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
}

TEST(GlWorker, TheGlProcessIsAFreshPxhNotAFork) {
    ASSERT_TRUE(kWorkerProgramSet);
    pxh::BackendSettings s;
    pxh::GlslChildBackend child(s);
    ASSERT_FALSE(child.in_process());
    ASSERT_GT(child.child_pid(), 0);
    const fs::path proc = "/proc/" + std::to_string(child.child_pid());
    // Its program is pxh's binary (a fork would still be pxh_tests) ...
    EXPECT_EQ(fs::canonical(proc / "exe"), fs::canonical(PXH_BINARY));
    EXPECT_NE(fs::canonical(proc / "exe"), fs::canonical("/proc/self/exe"));
    // ... in its worker mode, with the socket as fd 3 and nothing else of this process's open.
    const std::string cmdline = read_all(proc / "cmdline");
    EXPECT_NE(cmdline.find(std::string(pxh::kGlWorkerArg) + '\0' + "3" + '\0'), std::string::npos);
    for (const auto& e : fs::directory_iterator(proc / "fd")) {
        const int fd = std::stoi(e.path().filename().string());
        EXPECT_LE(fd, 3) << "the GL process holds fd " << fd << " -> "
                         << fs::read_symlink(e.path());
    }
    EXPECT_EQ(fs::read_symlink(proc / "fd" / "3").string().rfind("socket:", 0), 0u);
    // It made its context and says which.
    EXPECT_FALSE(child.facts().at("gl_renderer").empty());
}

// pxh runs its GL process through /proc/self/exe, a link: ps shows the binary it points to as
// the process's argv[0], not the link. Here a link of our own to pxh stands in for it.
TEST(GlWorker, TheGlProcessIsNamedByTheBinaryNotTheLink) {
    const fs::path dir = pxh::test::fresh_dir("gl_worker_link");
    const fs::path link = dir / "exe";
    fs::create_symlink(fs::canonical(PXH_BINARY), link);
    pxh::set_gl_worker_program(link.string());
    {
        pxh::BackendSettings s;
        pxh::GlslChildBackend child(s);
        ASSERT_GT(child.child_pid(), 0);
        const std::string cmdline =
            read_all("/proc/" + std::to_string(child.child_pid()) + "/cmdline");
        EXPECT_EQ(cmdline.substr(0, cmdline.find('\0')), fs::canonical(PXH_BINARY).string());
    }
    pxh::set_gl_worker_program(PXH_BINARY);
    fs::remove_all(dir);
}

TEST(GlWorker, WorkerModeWithoutItsSocketIsOneLineExit2) {
    const fs::path dir = pxh::test::fresh_dir("gl_worker_mode");
    for (const char* fd : {"99", "x", "-1", ""}) {
        const auto r = pxh::test::pxh_in(dir, std::string(pxh::kGlWorkerArg) + " '" + fd + "'");
        EXPECT_EQ(r.status, 2) << fd;
        EXPECT_EQ(r.err,
                  "pxh: error: the GL process's socket is not open (pxh starts this mode "
                  "itself)\n")
            << fd;
    }
    fs::remove_all(dir);
}

}  // namespace
