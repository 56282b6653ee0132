// The glsl backend as a run uses it: the GL work in a child process under a time limit (the
// models: dEQP's watchdog, piglit's one process per test). A shader that does not finish (a
// real GPU has no loop cap) cannot hang pxh: after gl_time_limit_s seconds on one row the child
// is killed, that row fails with the reason, and the next row starts a fresh child with a fresh
// GL context. A child that dies (a driver crash) fails its row the same way.
//
// The child is pxh itself started afresh (fork, then exec of pxh's binary in its hidden worker
// mode, gl_worker_main), made when the backend is created and again after a kill: a fork alone
// would carry into the child every lock another thread of pxh held at that moment (TBB's and
// Embree's workers, the allocator's, Mesa's) with no thread to release it, and the child could
// block forever on its first malloc. Between the fork and the exec the child makes only
// async-signal-safe calls. It gets its settings as the first message, holds a GlslBackend (the
// in-process backend, harness/backends/glsl_backend.h) and answers one request at a time over a
// socket pair: a draw (GlslDraw, as plain data: the program's
// sources and uniforms, the height field's texels, the view, the light, the method's built
// textures) answered with the MethodOutput, or a check of a program (compile, link, interface)
// answered with its problems. It dies with pxh (PR_SET_PDEATHSIG).
//
// The program started is pxh's binary: pxh's main() names itself (set_gl_worker_program), a
// program linking the library that is not pxh (pxh_tests) names pxh's binary. A program that
// names none draws in-process, without the time limit (in_process() says so).
//
// Adding a field to MethodOutput (or to GlslDraw): one line in its visit() in gl_wire.h,
// which both writes and reads it; a static_assert on sizeof(MethodOutput) there stops a build
// whose MethodOutput grew without it.
#pragma once
#include <sys/types.h>

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "harness/backends/backend.h"
#include "harness/backends/glsl_backend.h"

namespace pxh {

// The program the GL process runs (pxh's binary, started as `PROGRAM kGlWorkerArg FD`); empty:
// none (the backend draws in-process). Set once, before any backend is made.
void set_gl_worker_program(const std::string& path);
const std::string& gl_worker_program();
// pxh's hidden worker mode: argv[1] of a GL process. pxh's main() hands such a call to
// gl_worker_main before anything else.
inline constexpr const char* kGlWorkerArg = "--gl-worker-process";
// The GL process: serves requests on the socket `fd` (argv[2]) until pxh closes it; never
// returns (exit status 0 when pxh closed the socket, 2 for a bad fd argument).
[[noreturn]] void gl_worker_main(const char* fd);

class GlslChildBackend : public Backend {
  public:
    // Starts the child; std::runtime_error with its reason when its GL context cannot be made,
    // InputError for a --shader-dir that is not a folder.
    explicit GlslChildBackend(const BackendSettings& settings);
    ~GlslChildBackend() override;
    GlslChildBackend(const GlslChildBackend&) = delete;
    GlslChildBackend& operator=(const GlslChildBackend&) = delete;

    std::string name() const override { return "glsl"; }
    std::vector<Variant> variants() const override;
    MethodOutput run(const MethodSpec& m, const ViewInput& view, const Variant& v) override;
    std::string shader_of(const MethodInfo& m) const override;
    bool own_process() const override { return local_ == nullptr; }
    std::map<std::string, std::string> facts() const override { return facts_; }
    std::map<std::string, std::string> sources() const override {
        return local_ ? local_->compiled_sources() : sources_;
    }

    // A draw from plain data (the time limit applies).
    MethodOutput draw(const GlslDraw& d);
    // GlslBackend::check in the child: one line per problem, empty when none.
    std::vector<std::string> check(const GlslMethod& m, const GlUniforms& uniforms,
                                   const std::vector<uint8_t>& kinds = {});
    // Children killed (time limit) or lost (died) so far.
    int restarts() const { return restarts_; }
    pid_t child_pid() const { return pid_; }
    // True when it draws in this process (no child, no time limit): see above.
    bool in_process() const { return local_ != nullptr; }

  private:
    void start();
    void stop();
    // Sends one request and returns the child's answer; std::runtime_error when the time
    // limit passes or the child dies (it is then gone; the next request starts a fresh one).
    std::string exchange(const std::string& request);

    BackendSettings settings_;
    int fd_ = -1;
    pid_t pid_ = -1;
    int restarts_ = 0;
    std::map<std::string, std::string> facts_, sources_;
    std::unique_ptr<GlslBackend> local_;  // in-process fallback
};

}  // namespace pxh
