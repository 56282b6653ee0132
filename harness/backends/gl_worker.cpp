#include "harness/backends/gl_worker.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <stdexcept>
#include <type_traits>

#include "harness/core/error.h"

namespace pxh {
namespace {

// ---- The wire: one function per type, visit(A&, T&), both writes (Out) and reads (In) ----

class Out {
  public:
    std::string buf;
    void raw(const void* p, size_t n) { buf.append(static_cast<const char*>(p), n); }
    template <class T>
    void operator()(const T& v) {
        if constexpr (std::is_arithmetic_v<T> || std::is_enum_v<T>) {
            raw(&v, sizeof v);
        } else {
            visit(*this, const_cast<T&>(v));  // visit only reads through an Out
        }
    }
    void operator()(const std::string& s) {
        (*this)(uint64_t(s.size()));
        raw(s.data(), s.size());
    }
    template <class T>
    void operator()(const std::vector<T>& v) {
        (*this)(uint64_t(v.size()));
        if constexpr (std::is_trivially_copyable_v<T>) raw(v.data(), v.size() * sizeof(T));
        else
            for (const T& e : v) (*this)(e);
    }
    void operator()(const std::map<std::string, std::string>& m) {
        (*this)(uint64_t(m.size()));
        for (const auto& [k, v] : m) {
            (*this)(k);
            (*this)(v);
        }
    }
};

class In {
  public:
    explicit In(const std::string& s) : p_(s.data()), end_(s.data() + s.size()) {}
    void raw(void* d, size_t n) {
        if (size_t(end_ - p_) < n) throw std::runtime_error("GL process: a truncated message");
        if (n == 0) return;  // an empty vector's data() may be null: memcpy must not see it
        std::memcpy(d, p_, n);
        p_ += n;
    }
    template <class T>
    void operator()(T& v) {
        if constexpr (std::is_arithmetic_v<T> || std::is_enum_v<T>) raw(&v, sizeof v);
        else visit(*this, v);
    }
    size_t count(size_t element) {
        uint64_t n = 0;
        (*this)(n);
        if (element && n > size_t(end_ - p_) / element)
            throw std::runtime_error("GL process: a message with a bad length");
        return size_t(n);
    }
    void operator()(std::string& s) {
        s.resize(count(1));
        raw(s.data(), s.size());
    }
    template <class T>
    void operator()(std::vector<T>& v) {
        if constexpr (std::is_trivially_copyable_v<T>) {
            v.resize(count(sizeof(T)));
            raw(v.data(), v.size() * sizeof(T));
        } else {
            v.resize(count(1));
            for (T& e : v) (*this)(e);
        }
    }
    void operator()(std::map<std::string, std::string>& m) {
        const size_t n = count(2 * sizeof(uint64_t));
        for (size_t i = 0; i < n; ++i) {
            std::string k, v;
            (*this)(k);
            (*this)(v);
            m[k] = v;
        }
    }

  private:
    const char* p_;
    const char* end_;
};

static_assert(std::is_trivially_copyable_v<Vec2d> && std::is_trivially_copyable_v<Vec3d>);
static_assert(std::is_trivially_copyable_v<Footprint>);

template <class A>
void visit(A& a, Vec3d& v) {
    a(v.x), a(v.y), a(v.z);
}
template <class A>
void visit(A& a, Scene<double>& s) {
    a(s.scale), a(s.bias), a(s.V), a(s.width), a(s.height);
}
template <class A>
void visit(A& a, LightSpec& l) {
    a(l.theta_deg), a(l.phi_deg), a(l.layers_min), a(l.layers_max);
}
template <class A>
void visit(A& a, GlUniform& u) {
    a(u.name), a(u.type), a(u.value);
}
template <class A>
void visit(A& a, ResourceSpec& r) {  // what the GL side uses of it
    a(r.name), a(r.format), a(r.filter), a(r.wrap);
}
template <class A>
void visit(A& a, ResourceLevel& l) {
    a(l.width), a(l.height), a(l.texels);
}
template <class A>
void visit(A& a, HeightField& f) {  // what the GL side uses of it
    a(f.width), a(f.height), a(f.texels);
}
template <class A>
void visit(A& a, GlslMethod& m) {
    a(m.name), a(m.shader_file), a(m.has_builtin_text), a(m.builtin_text), a(m.declarations);
    a(m.plugin_shader), a(m.plugin_source), a(m.plugin_display), a(m.resources);
}

template <class A>
void visit(A& a, Spread& s) {
    a(s.median), a(s.min), a(s.max);
}
template <class A>
void visit(A& a, Timing& t) {
    a(t.unit), a(t.repeats), a(t.stats);
}
template <class A>
void visit(A& a, Counter& c) {  // a counter travels whole: a new one needs no line here
    a(c.name), a(c.value);
}
// Every field of MethodOutput, in one place: adding a field to it is one line here.
template <class A>
void visit(A& a, MethodOutput& o) {
    a(o.uv), a(o.fetches);
    a(o.shadow_hard), a(o.shadow_soft);
    a(o.timing), a(o.counters);
    a(o.shader), a(o.shader_sha256), a(o.samples_discarded);
}
// A MethodOutput that grew without a line above would come back from the child without the
// new field: update visit(MethodOutput) and then this size.
static_assert(sizeof(MethodOutput) == 272, "MethodOutput changed: update visit(MethodOutput)");

// A draw as it travels: the request owns what GlslDraw points to.
struct DrawData {
    GlslDraw d;
    HeightField hf;
    LightSpec light;
    MethodResources res;
    std::vector<Vec3d> V;
    std::vector<Vec2d> P;
    std::vector<uint8_t> inside;
    TextureLevels levels;
    std::vector<double> lambda;
    std::vector<Footprint> J;
};

enum : uint8_t { kDraw = 1, kCheck = 2 };

void write_draw(Out& o, const GlslDraw& d) {
    o(uint8_t(kDraw));
    o(d.method), o(d.uniforms), o(d.scene);
    o(d.hf->width), o(d.hf->height), o(d.hf->texels);
    o(d.samples), o(d.texture_format), o(d.frames);
    o(bool(d.light));
    if (d.light) o(*d.light);
    o(bool(d.resources));
    if (d.resources) {
        o(uint64_t(d.resources->items.size()));
        for (const BuiltResource& r : d.resources->items) o(r.image->levels);
    }
    o(bool(d.V));
    if (d.V) o(*d.V);
    o(bool(d.P));
    if (d.P) o(*d.P);
    o(bool(d.inside));
    if (d.inside) o(*d.inside);
    o(d.lod);
    o(bool(d.levels));
    if (d.levels) o(d.levels->levels);
    o(bool(d.lambda));
    if (d.lambda) o(*d.lambda);
    o(bool(d.J));
    if (d.J) o(*d.J);
}

void read_draw(In& in, DrawData& x) {
    GlslDraw& d = x.d;
    in(d.method), in(d.uniforms), in(d.scene);
    in(x.hf.width), in(x.hf.height), in(x.hf.texels);
    d.hf = &x.hf;
    in(d.samples), in(d.texture_format), in(d.frames);
    bool has = false;
    in(has);
    if (has) {
        in(x.light);
        d.light = &x.light;
    }
    in(has);
    if (has) {
        const size_t n = in.count(sizeof(uint64_t));
        if (n != d.method.resources.size())
            throw std::runtime_error("GL process: resources do not match the method's");
        for (size_t k = 0; k < n; ++k) {
            auto img = std::make_shared<ResourceImage>();
            in(img->levels);
            x.res.items.push_back({&d.method.resources[k], img, 0, 0});
        }
        d.resources = &x.res;
    }
    in(has);
    if (has) {
        in(x.V);
        d.V = &x.V;
    }
    in(has);
    if (has) {
        in(x.P);
        d.P = &x.P;
    }
    in(has);
    if (has) {
        in(x.inside);
        d.inside = &x.inside;
    }
    in(d.lod);
    in(has);
    if (has) {
        in(x.levels.levels);
        d.levels = &x.levels;
    }
    in(has);
    if (has) {
        in(x.lambda);
        d.lambda = &x.lambda;
    }
    in(has);
    if (has) {
        in(x.J);
        d.J = &x.J;
    }
}

// ---- Frames: a length, then the bytes ----

bool send_all(int fd, const char* p, size_t n) {
    while (n > 0) {
        const ssize_t w = ::send(fd, p, n, MSG_NOSIGNAL);
        if (w < 0 && errno == EINTR) continue;
        if (w <= 0) return false;
        p += w;
        n -= size_t(w);
    }
    return true;
}

bool send_frame(int fd, const std::string& payload) {
    const uint64_t n = payload.size();
    return send_all(fd, reinterpret_cast<const char*>(&n), sizeof n) &&
           send_all(fd, payload.data(), payload.size());
}

enum class Got { frame, closed, timeout };

// Reads one frame; deadline_ms < 0: no deadline.
Got recv_frame(int fd, std::string& out, std::chrono::steady_clock::time_point deadline,
               bool has_deadline) {
    auto read_n = [&](char* p, size_t n) -> Got {
        while (n > 0) {
            if (has_deadline) {
                const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
                                      deadline - std::chrono::steady_clock::now())
                                      .count();
                if (left <= 0) return Got::timeout;
                pollfd pfd{fd, POLLIN, 0};
                const int r = ::poll(&pfd, 1, int(std::min<long long>(left, 1 << 30)));
                if (r < 0 && errno == EINTR) continue;
                if (r == 0) return Got::timeout;
                if (r < 0) return Got::closed;
            }
            const ssize_t got = ::recv(fd, p, n, 0);
            if (got < 0 && errno == EINTR) continue;
            if (got <= 0) return Got::closed;
            p += got;
            n -= size_t(got);
        }
        return Got::frame;
    };
    uint64_t n = 0;
    if (const Got g = read_n(reinterpret_cast<char*>(&n), sizeof n); g != Got::frame) return g;
    if (n > (uint64_t(1) << 40)) return Got::closed;
    out.resize(size_t(n));
    return read_n(out.data(), out.size());
}

// What the GL process needs of the settings: its first message.
template <class A>
void visit(A& a, BackendSettings& s) {
    a(s.shader_dir), a(s.gl_frames), a(s.texture_formats), a(s.gl);
}

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

GlslChildBackend::GlslChildBackend(const BackendSettings& settings) : settings_(settings) {
    if (!settings_.shader_dir.empty()) {
        // A typo must not silently give the built-in shaders' numbers.
        std::error_code ec;
        if (!std::filesystem::is_directory(settings_.shader_dir, ec))
            throw InputError("--shader-dir " + settings_.shader_dir, "no such folder");
    }
    if (gl_worker_program().empty()) {  // no pxh binary to start: draw here
        local_ = std::make_unique<GlslBackend>(GlslOptions{
            settings_.shader_dir, settings_.gl_frames, settings_.texture_formats, settings_.gl});
        facts_ = local_->facts();
        return;
    }
    start();
}

GlslChildBackend::~GlslChildBackend() { stop(); }

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

std::vector<Variant> GlslChildBackend::variants() const {
    std::vector<Variant> out;
    for (const auto& f : settings_.texture_formats) out.push_back({"float", f});
    return out;
}

std::string GlslChildBackend::shader_of(const MethodInfo& m) const {
    return glsl_shader_description(GlslMethod::of(m), settings_.shader_dir);
}

MethodOutput GlslChildBackend::draw(const GlslDraw& d) {
    if (local_) return local_->draw(d);
    Out req;
    write_draw(req, d);
    const std::string answer = exchange(req.buf);
    In in(answer);
    uint8_t status = 0;
    in(status);
    if (status != 1) {
        std::string why;
        in(why);
        if (status == 2) throw std::logic_error(why);
        throw std::runtime_error(why);
    }
    MethodOutput out;
    in(out);
    in(sources_);
    return out;
}

MethodOutput GlslChildBackend::run(const MethodSpec& m, const ViewInput& view, const Variant& v) {
    return draw(glsl_draw_of(m, view, v));
}

std::vector<std::string> GlslChildBackend::check(const GlslMethod& m, const GlUniforms& uniforms,
                                                 const std::vector<uint8_t>& kinds) {
    if (local_) return local_->check(m, uniforms, kinds);
    Out req;
    req(uint8_t(kCheck));
    req(m), req(uniforms), req(kinds);
    const std::string answer = exchange(req.buf);
    In in(answer);
    uint8_t status = 0;
    in(status);
    if (status != 1) {
        std::string why;
        in(why);
        return {why};
    }
    std::vector<std::string> problems;
    in(problems);
    in(sources_);
    return problems;
}

std::unique_ptr<Backend> make_glsl_backend(const BackendSettings& s) {
    return std::make_unique<GlslChildBackend>(s);
}

}  // namespace pxh
