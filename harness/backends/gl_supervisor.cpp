// The GL process supervised (GlslChildBackend, harness/backends/gl_worker.h): started by fork
// and exec, handed its settings, each request answered within gl_time_limit_s or the process
// killed (or found dead) and the row failed with the reason.
#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <stdexcept>

#include "harness/backends/gl_wire.h"
#include "harness/backends/gl_worker.h"

namespace pxh {

using namespace gl_wire;

namespace {

std::string describe_status(int status) {
    if (WIFSIGNALED(status)) {
        const int sig = WTERMSIG(status);
        const char* name = strsignal(sig);
        return "died with signal " + std::to_string(sig) +
               (name ? std::string(" (") + name + ")" : "");
    }
    if (WIFEXITED(status)) return "exited with status " + std::to_string(WEXITSTATUS(status));
    return "stopped";
}

std::string seconds(double s) {
    std::ostringstream os;
    os << s;
    return os.str();
}

}  // namespace

void GlslChildBackend::stop() {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
    if (pid_ > 0) {
        ::kill(pid_, SIGKILL);
        int status = 0;
        while (::waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
        }
    }
    pid_ = -1;
}

void GlslChildBackend::start() {
    // Everything the child needs between fork and exec is made here: after the fork it makes
    // only async-signal-safe calls (another thread's lock held at the fork is never released).
    const std::string& program = gl_worker_program();
    constexpr int kChildFd = 3;
    const std::string fd_arg = std::to_string(kChildFd);
    // What ps shows as its argv[0]: the binary's own path, not the /proc/self/exe it is run by.
    std::error_code no_link;
    const std::filesystem::path target = std::filesystem::read_symlink(program, no_link);
    const std::string shown = no_link ? program : target.string();
    std::vector<char*> argv{const_cast<char*>(shown.c_str()), const_cast<char*>(kGlWorkerArg),
                            const_cast<char*>(fd_arg.c_str()), nullptr};
    Out failed;  // the hello of a child whose exec failed
    failed(uint8_t(0));
    failed(std::string("glsl: cannot start the GL process: cannot run ") + program);
    std::string failed_frame;
    {
        const uint64_t n = failed.buf.size();
        failed_frame.assign(reinterpret_cast<const char*>(&n), sizeof n);
        failed_frame += failed.buf;
    }
    Out first;  // the settings, the child's first message
    first(settings_);
    int sv[2];
    if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, sv) != 0)
        throw std::runtime_error(std::string("glsl: cannot create the GL process's socket: ") +
                                 std::strerror(errno));
    const pid_t parent = ::getpid();
    const pid_t pid = ::fork();
    if (pid < 0) {
        ::close(sv[0]);
        ::close(sv[1]);
        throw std::runtime_error(std::string("glsl: cannot start the GL process: ") +
                                 std::strerror(errno));
    }
    if (pid == 0) {
        ::prctl(PR_SET_PDEATHSIG, SIGKILL);  // it dies with pxh
        if (::getppid() != parent) _exit(0);
        // The socket as fd 3, open across the exec; nothing else of pxh's but stdio (a results
        // folder's lock stays pxh's).
        if (sv[1] == kChildFd ? ::fcntl(kChildFd, F_SETFD, 0) != 0
                              : ::dup2(sv[1], kChildFd) != kChildFd)
            _exit(127);
        ::close_range(kChildFd + 1, ~0U, 0);
        ::execv(program.c_str(), argv.data());
        const ssize_t w = ::write(kChildFd, failed_frame.data(), failed_frame.size());
        (void)w;
        _exit(127);
    }
    ::close(sv[1]);
    fd_ = sv[0];
    pid_ = pid;
    if (!send_frame(fd_, first.buf)) {
        stop();
        throw std::runtime_error("glsl: the GL process ended before it made a context");
    }
    // The hello: the context's facts, or why it could not be made.
    std::string hello;
    const auto deadline = std::chrono::steady_clock::now() +
                          std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                              std::chrono::duration<double>(settings_.gl_time_limit_s));
    const Got g = recv_frame(fd_, hello, deadline, true);
    if (g != Got::frame) {
        stop();
        throw std::runtime_error(
            g == Got::timeout ? "glsl: the GL process made no context within " +
                                    seconds(settings_.gl_time_limit_s) + " s (gl_time_limit_s)"
                              : std::string("glsl: the GL process ended before it made "
                                            "a context"));
    }
    In in(hello);
    uint8_t ok = 0;
    in(ok);
    if (!ok) {
        std::string why;
        in(why);
        stop();
        throw std::runtime_error(why);
    }
    facts_.clear();
    in(facts_);
}

std::string GlslChildBackend::exchange(const std::string& request) {
    if (pid_ < 0) start();
    const auto deadline = std::chrono::steady_clock::now() +
                          std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                              std::chrono::duration<double>(settings_.gl_time_limit_s));
    std::string answer;
    Got g = send_frame(fd_, request) ? recv_frame(fd_, answer, deadline, true) : Got::closed;
    if (g == Got::frame) return answer;
    ++restarts_;
    if (g == Got::timeout) {
        stop();
        throw std::runtime_error(
            "GL time limit: the row's GL work did not finish within " +
            seconds(settings_.gl_time_limit_s) +
            " s (gl_time_limit_s, pxh run --gl-time-limit); its GL process was killed and the "
            "next row runs in a fresh GL context");
    }
    ::close(fd_);
    fd_ = -1;
    int status = 0;
    while (::waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
    }
    pid_ = -1;
    throw std::runtime_error("the GL process " + describe_status(status) +
                             " during the row's GL work (a driver crash?); the next row runs "
                             "in a fresh GL context");
}

}  // namespace pxh
