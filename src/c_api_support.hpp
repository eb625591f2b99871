// The C API's plumbing, shared by c_api.cpp and libgfmd_mpi's c_api_mpi.cpp: the handle, and
// every exception turned into a status plus message at the extern "C" boundary.
#ifndef GFMD_SRC_C_API_SUPPORT_HPP
#define GFMD_SRC_C_API_SUPPORT_HPP

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <exception>
#include <memory>
#include <new>
#include <string>
#include <utility>

#include "error.hpp"
#include "gfmd.h"
#include "simulation.hpp"

struct gfmd_sim {
    std::unique_ptr<gfmd::Simulation> sim;
    mutable std::string last_error;
};

namespace gfmd {
namespace capi {

inline void record(const gfmd_sim *s, const char *msg) noexcept {
    try {
        s->last_error = msg;
    } catch (...) {
        s->last_error.clear();  // cannot store the message: the status still says what failed
    }
}

// Run f, turning every exception into its status; report(message) receives the message of a
// failure (a handle's last error, a caller's buffer, or nothing for calls without either).
template <class F, class Report>
int32_t status_of(F &&f, Report &&report) noexcept {
    try {
        f();
        return GFMD_OK;
    } catch (const gfmd::Error &e) {
        report(e.what());
        return e.status();
    } catch (const std::bad_alloc &) {
        report("out of memory");
        return GFMD_ERR_NOMEM;
    } catch (const std::exception &e) {
        report(e.what());
        return GFMD_ERR_INTERNAL;
    } catch (...) {
        report("unknown internal error");
        return GFMD_ERR_INTERNAL;
    }
}

template <class F>
int32_t status_of(F &&f) noexcept {
    return status_of(std::forward<F>(f), [](const char *) {});
}

// A call that makes a handle from a file: *out is NULL unless it succeeds, and the caller's buffer
// (errbuf, errlen bytes; may be NULL) receives the message of every failure, the early ones
// included ("" on success).  make(path) returns the new handle's unique_ptr.
template <class Handle, class Make>
int32_t make_from_file(const char *path, Handle **out, char *errbuf, int64_t errlen, Make &&make) noexcept {
    auto report = [&](const char *msg) {
        if (errbuf != nullptr && errlen > 0) std::snprintf(errbuf, static_cast<std::size_t>(errlen), "%s", msg);
    };
    report("");
    if (out != nullptr) *out = nullptr;
    return status_of(
        [&] {
            if (out == nullptr) fail(GFMD_ERR_NULL, "argument 'out' is NULL");
            if (path == nullptr) fail(GFMD_ERR_NULL, "argument 'path' is NULL");
            *out = make(path).release();
        },
        report);
}

// A handle's message m into the caller's buffer (len bytes, always terminated).
inline int32_t copy_message(const std::string &m, char *buf, int64_t len) noexcept {
    if (buf == nullptr) return GFMD_ERR_NULL;
    if (len <= 0) return GFMD_ERR_INVALID_ARG;
    const std::size_t cap = static_cast<std::size_t>(len) - 1;
    const std::size_t n = m.size() < cap ? m.size() : cap;
    std::memcpy(buf, m.data(), n);
    buf[n] = '\0';
    return (m.size() > cap) ? GFMD_ERR_TRUNCATED : GFMD_OK;
}

// Run f on a valid handle; translate exceptions.  The message of the last failure stays in the
// handle until the next failure.
// A fingerprint of a call's arguments: the bytes of each value, the contents of a string, whether
// each other pointer is NULL.  A distributed handle's call checks that every rank passed the same,
// so that a value that is bad on one rank fails on all before anything changes.
class ArgPrint {
public:
    void add(const char *text) {
        mix(text != nullptr);
        if (text != nullptr)
            for (const char *c = text; *c != '\0'; ++c) mix(static_cast<unsigned char>(*c));
    }
    template <class T>
    void add(T *p) {
        mix(p != nullptr);
    }
    template <class T>
    void add(T value) {
        unsigned char b[sizeof(T)];
        std::memcpy(b, &value, sizeof(T));
        for (unsigned char c : b) mix(c);
    }
    uint64_t value() const { return h_; }

private:
    void mix(unsigned char c) { h_ = (h_ ^ c) * 1099511628211u; }  // FNV-1a
    uint64_t h_ = 14695981039346656037u;
};

constexpr const char *kOtherArguments =
    "a collective call got other arguments on another rank (values, or which pointers are NULL)";

template <class... A>
uint64_t args(A... a) {
    ArgPrint p;
    (p.add(a), ...);
    return p.value();
}

// Run f on a valid handle; translate exceptions.  The message of the last failure stays in the
// handle until the next failure.  A distributed handle's call is collective: the ranks first check
// that they passed the same arguments, and every rank returns the status and message of the
// lowest failing rank.
template <class F>
int32_t guarded(const gfmd_sim *s, uint64_t arguments, F &&f) noexcept {
    if (s == nullptr || !s->sim) return GFMD_ERR_NULL;
    const FftGrid &grid = s->sim->grid();
    std::string message;
    int32_t status = GFMD_OK;
    if (grid.distributed() && !grid.same_on_all_ranks(arguments)) {
        status = GFMD_ERR_INVALID_ARG;
        message = kOtherArguments;
    } else {
        status = status_of([&] { f(*s->sim); }, [&](const char *msg) {
            try {
                message = msg;
            } catch (...) {
                message.clear();
            }
        });
        if (grid.distributed()) status = grid.agree(status, message);
    }
    if (status != GFMD_OK) record(s, message.c_str());
    return status;
}

template <class F>
int32_t guarded(const gfmd_sim *s, F &&f) noexcept {
    return guarded(s, args(), std::forward<F>(f));
}

// Whole-grid fields of a handle distributed over several ranks would not fit one rank (a 65536^2
// field is 34 GB): those calls are refused, the local-slab calls of gfmd_mpi.h take their place.
inline void whole_grid(const Simulation &m, const char *instead) {
    if (m.grid().ranks() > 1)
        fail(GFMD_ERR_STATE, std::string("this handle is distributed over ") + std::to_string(m.grid().ranks()) +
                                 " ranks: whole-grid fields are refused; use " + instead);
}

template <class T>
void need(const T *p, const char *name) {
    if (p == nullptr) fail(GFMD_ERR_NULL, std::string("argument '") + name + "' is NULL");
}

}  // namespace capi
}  // namespace gfmd

#endif
