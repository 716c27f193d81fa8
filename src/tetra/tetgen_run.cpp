// TetGen in a child process. The child builds TetGen's input, runs it, and writes the output
// (or the code TetGen threw) to a pipe; the parent reads until EOF or the deadline, kills the
// child past it, and turns every way of ending (exit, throw, signal, timeout) into a result.
#define TETLIBRARY
#include <tetgen.h>

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdint>
#include <cstring>

#include "tetra/tetgen_run.h"

#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#define THICKET_HAS_ASAN 1
#endif
#endif
#ifndef THICKET_HAS_ASAN
#define THICKET_HAS_ASAN 0
#endif

namespace thicket::tetra_detail {

namespace {

constexpr int kBoxFacets[6][4] = {{0, 1, 3, 2}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 3, 7, 5}};

/// Appends `count` ints or doubles (as bytes) after their count.
template <class T>
void put(std::string& buf, const T* data, size_t count) {
    const uint64_t n = count;
    buf.append(reinterpret_cast<const char*>(&n), sizeof n);
    if (count) buf.append(reinterpret_cast<const char*>(data), count * sizeof(T));
}

/// Reads an array written by put(); false when the bytes end first.
template <class T>
bool get(const std::string& buf, size_t& pos, std::vector<T>& out) {
    uint64_t n = 0;
    if (buf.size() - pos < sizeof n) return false;
    std::memcpy(&n, buf.data() + pos, sizeof n);
    pos += sizeof n;
    if (n > (buf.size() - pos) / sizeof(T)) return false;
    out.resize(n);
    if (n) std::memcpy(out.data(), buf.data() + pos, n * sizeof(T));
    pos += n * sizeof(T);
    return true;
}

/// Makes `f` one polygon of the n vertex ids `ids` (TetGen frees it with the tetgenio).
void init_facet(tetgenio::facet& f, const int* ids, int n) {
    tetgenio::init(&f);
    f.numberofpolygons = 1;
    f.polygonlist = new tetgenio::polygon[1];
    tetgenio::init(&f.polygonlist[0]);
    f.polygonlist[0].numberofvertices = n;
    f.polygonlist[0].vertexlist = new int[n];
    for (int k = 0; k < n; ++k) f.polygonlist[0].vertexlist[k] = ids[k];
}

/// The child's work: the bytes to send (status int, then the arrays).
std::string child_run(const TetgenInput& in, const std::string& switches) {
    tetgenio tin, tout;
    tin.firstnumber = 0;
    tin.numberofpoints = int(in.points.size() / 3);
    tin.pointlist = new REAL[in.points.size()];
    for (size_t i = 0; i < in.points.size(); ++i) tin.pointlist[i] = in.points[i];
    const int tris = int(in.markers.size());
    tin.numberoffacets = 6 + tris;
    tin.facetlist = new tetgenio::facet[tin.numberoffacets];
    tin.facetmarkerlist = new int[tin.numberoffacets];
    for (int f = 0; f < 6; ++f) {
        init_facet(tin.facetlist[f], kBoxFacets[f], 4);
        tin.facetmarkerlist[f] = -1;
    }
    for (int t = 0; t < tris; ++t) {
        init_facet(tin.facetlist[6 + t], &in.triangles[3 * size_t(t)], 3);
        tin.facetmarkerlist[6 + t] = in.markers[t];
    }
    std::string buf;
    int status = 0;
    try {
        std::vector<char> sw(switches.begin(), switches.end());
        sw.push_back('\0');
        tetrahedralize(sw.data(), &tin, &tout);
    } catch (int code) {
        status = code == 0 ? -1 : code;
    } catch (...) {
        status = 2;
    }
    buf.append(reinterpret_cast<const char*>(&status), sizeof status);
    if (status != 0) return buf;
    put(buf, tout.pointlist, size_t(tout.numberofpoints) * 3);
    put(buf, tout.tetrahedronlist, size_t(tout.numberoftetrahedra) * 4);
    put(buf, tout.neighborlist, tout.neighborlist ? size_t(tout.numberoftetrahedra) * 4 : 0);
    put(buf, tout.trifacelist, size_t(tout.numberoftrifaces) * 3);
    put(buf, tout.trifacemarkerlist, tout.trifacemarkerlist ? size_t(tout.numberoftrifaces) : 0);
    return buf;
}

/// What TetGen's thrown code means (terminatetetgen's codes in tetgen.h).
std::string code_text(int code) {
    switch (code) {
    case 1: return "TetGen ran out of memory";
    case 2: return "TetGen reported an internal error";
    case 3: return "TetGen found a self-intersection";
    case 4: return "TetGen found a feature below its tolerance";
    case 5: return "TetGen found two very close facets";
    case 10: return "TetGen reported an input error";
    default: return "TetGen stopped with code " + std::to_string(code);
    }
}

}  // namespace

TetgenResult run_tetgen(const TetgenInput& in, const std::string& switches, double seconds, size_t memory_mb) {
    TetgenResult r;
    const auto start = std::chrono::steady_clock::now();
    auto elapsed_ms = [&] {
        return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    };
    int fds[2];
    if (pipe(fds) != 0) {
        r.failure = std::string("cannot make a pipe for TetGen: ") + std::strerror(errno);
        return r;
    }
    const pid_t pid = fork();
    if (pid < 0) {
        close(fds[0]);
        close(fds[1]);
        r.failure = std::string("cannot start TetGen's process: ") + std::strerror(errno);
        return r;
    }
    if (pid == 0) {
        close(fds[0]);
        const int null = open("/dev/null", O_WRONLY);
        if (null >= 0) {
            dup2(null, 1);
            dup2(null, 2);
        }
        // AddressSanitizer reserves terabytes of address space up front: no RLIMIT_AS under it. g++
        // says so by __SANITIZE_ADDRESS__, clang by __has_feature; THICKET_SANITIZED covers both.
#if !defined(__SANITIZE_ADDRESS__) && !defined(THICKET_SANITIZED) && !THICKET_HAS_ASAN
        const rlim_t bytes = rlim_t(memory_mb) << 20;
        const rlimit limit{bytes, bytes};
        setrlimit(RLIMIT_AS, &limit);
#else
        (void)memory_mb;
#endif
        const std::string buf = child_run(in, switches);
        size_t done = 0;
        while (done < buf.size()) {
            const ssize_t w = write(fds[1], buf.data() + done, buf.size() - done);
            if (w < 0 && errno == EINTR) continue;
            if (w <= 0) _exit(3);
            done += size_t(w);
        }
        _exit(0);
    }
    close(fds[1]);
    std::string buf;
    bool timed_out = false;
    char chunk[1 << 16];
    while (true) {
        const double left_ms = seconds * 1000.0 - elapsed_ms();
        if (left_ms <= 0) {
            timed_out = true;
            break;
        }
        pollfd p{fds[0], POLLIN, 0};
        const int ready = poll(&p, 1, int(std::min(left_ms, 1000.0)) + 1);
        if (ready < 0 && errno == EINTR) continue;
        if (ready <= 0) continue;
        const ssize_t n = read(fds[0], chunk, sizeof chunk);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) break;
        buf.append(chunk, size_t(n));
    }
    close(fds[0]);
    if (timed_out) kill(pid, SIGKILL);
    int wstatus = 0;
    while (waitpid(pid, &wstatus, 0) < 0 && errno == EINTR) {
    }
    r.ms = elapsed_ms();
    if (timed_out) {
        r.failure = "TetGen ran past the time limit of " + std::to_string(int(seconds)) + " s";
        return r;
    }
    if (WIFSIGNALED(wstatus)) {
        r.failure = "TetGen crashed (signal " + std::to_string(WTERMSIG(wstatus)) + ")";
        return r;
    }
    int status = 0;
    size_t pos = sizeof status;
    if (buf.size() < sizeof status || !WIFEXITED(wstatus) || WEXITSTATUS(wstatus) != 0) {
        r.failure = "TetGen's process ended without an answer (out of its " + std::to_string(memory_mb) +
                    " MiB of memory?)";
        return r;
    }
    std::memcpy(&status, buf.data(), sizeof status);
    if (status != 0) {
        r.failure = code_text(status);
        return r;
    }
    TetgenOutput& o = r.out;
    if (!get(buf, pos, o.points) || !get(buf, pos, o.tets) || !get(buf, pos, o.neighbors) ||
        !get(buf, pos, o.faces) || !get(buf, pos, o.face_markers) || pos != buf.size()) {
        r.failure = "TetGen's answer was cut short";
        return r;
    }
    r.ok = true;
    return r;
}

}  // namespace thicket::tetra_detail
