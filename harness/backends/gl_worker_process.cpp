// The GL process itself: pxh's hidden worker mode (gl_worker_main) serving draws and checks
// with a GlslBackend until pxh closes the socket; the program that is started as it.
#include <fcntl.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <memory>

#include "harness/backends/gl_wire.h"
#include "harness/backends/gl_worker.h"

namespace pxh {
namespace {

using namespace gl_wire;

// The child: a GlslBackend answering requests until pxh closes the socket.
[[noreturn]] void serve(int fd) {
    std::unique_ptr<GlslBackend> gl;
    {
        Out hello;
        try {
            std::string first;
            if (recv_frame(fd, first, {}, false) != Got::frame) _exit(0);
            BackendSettings s;
            In in(first);
            in(s);
            gl = std::make_unique<GlslBackend>(
                GlslOptions{s.shader_dir, s.gl_frames, s.texture_formats, s.gl});
            hello(uint8_t(1));
            hello(gl->facts());
        } catch (const std::exception& e) {
            hello(uint8_t(0));
            hello(std::string(e.what()));
            send_frame(fd, hello.buf);
            _exit(0);
        }
        if (!send_frame(fd, hello.buf)) _exit(0);
    }
    for (;;) {
        std::string req;
        if (recv_frame(fd, req, {}, false) != Got::frame) _exit(0);
        Out answer;
        try {
            In in(req);
            uint8_t type = 0;
            in(type);
            if (type == kDraw) {
                DrawData x;
                read_draw(in, x);
                const MethodOutput out = gl->draw(x.d);
                answer(uint8_t(1));
                answer(out);
                answer(gl->compiled_sources());
            } else if (type == kCheck) {
                GlslMethod m;
                GlUniforms u;
                std::vector<uint8_t> kinds;
                in(m), in(u), in(kinds);
                const std::vector<std::string> problems = gl->check(m, u, kinds);
                answer(uint8_t(1));
                answer(problems);
                answer(gl->compiled_sources());
            } else {
                throw std::logic_error("GL process: unknown request " + std::to_string(type));
            }
        } catch (const std::logic_error& e) {
            answer = Out();
            answer(uint8_t(2));
            answer(std::string(e.what()));
        } catch (const std::exception& e) {
            answer = Out();
            answer(uint8_t(0));
            answer(std::string(e.what()));
        }
        if (!send_frame(fd, answer.buf)) _exit(0);
    }
}

std::string& worker_program() {
    static std::string path;
    return path;
}

}  // namespace

void set_gl_worker_program(const std::string& path) { worker_program() = path; }
const std::string& gl_worker_program() { return worker_program(); }

void gl_worker_main(const char* fd_arg) {
    char* end = nullptr;
    const long fd = std::strtol(fd_arg, &end, 10);
    if (end == fd_arg || *end || fd < 0 || fd > 1 << 20 || ::fcntl(int(fd), F_GETFD) < 0) {
        std::fputs(
            "pxh: error: the GL process's socket is not open (pxh starts this mode "
            "itself)\n",
            stderr);
        _exit(2);
    }
    serve(int(fd));
}

}  // namespace pxh
