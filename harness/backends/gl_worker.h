// The glsl backend as a run uses it: the GL work in a child process under a time limit (the
// models: dEQP's watchdog, piglit's one process per test). A shader that does not finish (a
// real GPU has no loop cap) cannot hang pxh: after gl_time_limit_s seconds on one row the child
// is killed, that row fails with the reason, and the next row starts a fresh child with a fresh
// GL context. A child that dies (a driver crash) fails its row the same way.
//
// The child is a fork of pxh, made when the backend is created and again after a kill; it holds
// a GlslBackend (the in-process backend, harness/backends/glsl_backend.h) and answers one
// request at a time over a socket pair: a draw (GlslDraw, as plain data: the program's
// sources and uniforms, the height field's texels, the view, the light, the method's built
// textures) answered with the MethodOutput, or a check of a program (compile, link, interface)
// answered with its problems. It dies with pxh (PR_SET_PDEATHSIG).
//
// A process that has made a GL context itself (a test's in-process GlslBackend) cannot fork a
// GL child safely: the child would inherit Mesa's state without its threads and can deadlock.
// There (harness/gl/context.h: gl_context_made_in_process) the backend draws in-process, without
// the time limit (in_process() says so); pxh itself never makes a context outside the child.
//
// Adding a field to MethodOutput (or to GlslDraw): one line in its visit() in gl_worker.cpp,
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
    std::map<std::string, std::string> facts() const override { return facts_; }
    std::map<std::string, std::string> sources() const override {
        return local_ ? local_->compiled_sources() : sources_;
    }

    // A draw from plain data (the time limit applies).
    MethodOutput draw(const GlslDraw& d);
    // GlslBackend::check in the child: one line per problem, empty when none.
    std::vector<std::string> check(const GlslMethod& m, const GlUniforms& uniforms);
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
