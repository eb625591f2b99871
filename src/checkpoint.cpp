// Checkpoint and restart: a simulation's complete state in a portable, versioned binary file.
//
// Format version 1, every number little-endian whatever the machine:
//   "GFMDCKPT"                      8 bytes, magic
//   u32 version = 1, u32 flags = 0
//   i64 nx, ny; f64 lx, ly
//   f64 e_star; i32 kind; f64 width, nu, sigma0, gamma0, rho, dt_user, eta_user
//   i32 solver, threads (informative; not restored), planner
//   f64 fire_dt, fire_alpha; i64 fire_positive
//   f64 h[nx*ny], z[nx*ny], v[nx*ny]    (x fastest)
//   u64 FNV-1a hash of every byte before it
// Readers refuse other magics, versions they do not know, truncation and hash mismatches.
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>
#include <string>

#include "error.hpp"
#include "simulation.hpp"

namespace gfmd {

namespace {

constexpr char kMagic[8] = {'G', 'F', 'M', 'D', 'C', 'K', 'P', 'T'};
constexpr uint32_t kVersion = 1;

struct File {
    std::FILE *f = nullptr;
    ~File() {
        if (f != nullptr) std::fclose(f);
    }
};

class Writer {
public:
    Writer(std::FILE *f, const std::string &path) : f_(f), path_(path) {}
    void bytes(const void *p, std::size_t n) {
        const auto *b = static_cast<const unsigned char *>(p);
        for (std::size_t i = 0; i < n; ++i) hash_ = (hash_ ^ b[i]) * 0x100000001b3ULL;
        if (std::fwrite(p, 1, n, f_) != n) fail(GFMD_ERR_IO, "cannot write '" + path_ + "'");
    }
    void u64(uint64_t x) {
        unsigned char b[8];
        for (int i = 0; i < 8; ++i) b[i] = static_cast<unsigned char>(x >> (8 * i));
        bytes(b, 8);
    }
    void u32(uint32_t x) {
        unsigned char b[4];
        for (int i = 0; i < 4; ++i) b[i] = static_cast<unsigned char>(x >> (8 * i));
        bytes(b, 4);
    }
    void i64(int64_t x) { u64(static_cast<uint64_t>(x)); }
    void i32(int32_t x) { u32(static_cast<uint32_t>(x)); }
    void f64(double x) {
        uint64_t u;
        std::memcpy(&u, &x, 8);
        u64(u);
    }
    void array(const double *a, int64_t n) {
        // In blocks, so that a 4096^2 field needs no second copy in memory.
        unsigned char buf[8 * 1024];
        for (int64_t i = 0; i < n;) {
            int64_t m = 0;
            for (; m < 1024 && i < n; ++m, ++i) {
                uint64_t u;
                std::memcpy(&u, &a[i], 8);
                for (int k = 0; k < 8; ++k) buf[8 * m + k] = static_cast<unsigned char>(u >> (8 * k));
            }
            bytes(buf, static_cast<std::size_t>(8 * m));
        }
    }
    uint64_t hash() const { return hash_; }

private:
    std::FILE *f_;
    std::string path_;
    uint64_t hash_ = 0xcbf29ce484222325ULL;
};

class Reader {
public:
    Reader(std::FILE *f, const std::string &path) : f_(f), path_(path) {}
    void bytes(void *p, std::size_t n) {
        if (std::fread(p, 1, n, f_) != n)
            fail(GFMD_ERR_FORMAT, "'" + path_ + "' is truncated: not a complete gfmd checkpoint");
        const auto *b = static_cast<const unsigned char *>(p);
        for (std::size_t i = 0; i < n; ++i) hash_ = (hash_ ^ b[i]) * 0x100000001b3ULL;
    }
    uint64_t u64() {
        unsigned char b[8];
        bytes(b, 8);
        uint64_t x = 0;
        for (int i = 0; i < 8; ++i) x |= static_cast<uint64_t>(b[i]) << (8 * i);
        return x;
    }
    uint32_t u32() {
        unsigned char b[4];
        bytes(b, 4);
        uint32_t x = 0;
        for (int i = 0; i < 4; ++i) x |= static_cast<uint32_t>(b[i]) << (8 * i);
        return x;
    }
    int64_t i64() { return static_cast<int64_t>(u64()); }
    int32_t i32() { return static_cast<int32_t>(u32()); }
    double f64() {
        const uint64_t u = u64();
        double x;
        std::memcpy(&x, &u, 8);
        return x;
    }
    void array(double *a, int64_t n) {
        unsigned char buf[8 * 1024];
        for (int64_t i = 0; i < n;) {
            const int64_t m = std::min<int64_t>(1024, n - i);
            bytes(buf, static_cast<std::size_t>(8 * m));
            for (int64_t j = 0; j < m; ++j, ++i) {
                uint64_t u = 0;
                for (int k = 0; k < 8; ++k) u |= static_cast<uint64_t>(buf[8 * j + k]) << (8 * k);
                std::memcpy(&a[i], &u, 8);
            }
        }
    }
    uint64_t hash() const { return hash_; }

private:
    std::FILE *f_;
    std::string path_;
    uint64_t hash_ = 0xcbf29ce484222325ULL;
};

}  // namespace

void Simulation::save(const char *path) const {
    const std::string p(path);
    // Write to a temporary name, then rename: a crash while saving never leaves a damaged
    // checkpoint under the final name.
    const std::string tmp = p + ".tmp";
    File file;
    file.f = std::fopen(tmp.c_str(), "wb");
    if (file.f == nullptr) fail(GFMD_ERR_IO, "cannot create '" + tmp + "'");
    Writer w(file.f, tmp);
    w.bytes(kMagic, 8);
    w.u32(kVersion);
    w.u32(0);
    w.i64(grid_.nx());
    w.i64(grid_.ny());
    w.f64(grid_.lx());
    w.f64(grid_.ly());
    w.f64(e_star_);
    w.i32(kind_);
    w.f64(width_);
    w.f64(nu_);
    w.f64(sigma0_);
    w.f64(gamma0_);
    w.f64(rho_);
    w.f64(dt_user_);
    w.f64(eta_user_);
    w.i32(solver_);
    w.i32(threads_);
    w.i32(planner_);
    w.f64(fire_dt_);
    w.f64(fire_alpha_);
    w.i64(fire_positive_);
    w.array(h_.data(), n_);
    w.array(z_.data(), n_);
    w.array(v_.data(), n_);
    w.u64(w.hash());
    const bool ok = std::fflush(file.f) == 0 && std::fclose(file.f) == 0;
    file.f = nullptr;
    if (!ok || std::rename(tmp.c_str(), path) != 0) {
        std::remove(tmp.c_str());
        fail(GFMD_ERR_IO, "cannot write '" + p + "'");
    }
}

std::unique_ptr<Simulation> Simulation::load(const char *path, bool (*fits)(int64_t, int64_t)) {
    const std::string p(path);
    File file;
    file.f = std::fopen(path, "rb");
    if (file.f == nullptr) fail(GFMD_ERR_IO, "cannot open '" + p + "'");
    Reader r(file.f, p);
    char magic[8];
    r.bytes(magic, 8);
    if (std::memcmp(magic, kMagic, 8) != 0) fail(GFMD_ERR_FORMAT, "'" + p + "' is not a gfmd checkpoint");
    const uint32_t version = r.u32();
    if (version != kVersion)
        fail(GFMD_ERR_VERSION, "'" + p + "' is a checkpoint of format version " + std::to_string(version) +
                                   "; this library reads version " + std::to_string(kVersion));
    r.u32();  // flags, none defined
    const int64_t nx = r.i64(), ny = r.i64();
    const double lx = r.f64(), ly = r.f64();
    if (nx <= 0 || ny <= 0 || nx > (INT64_C(1) << 30) || ny > (INT64_C(1) << 30) || !(lx >= kMinLength) ||
        !(lx <= kMaxLength) || !(ly >= kMinLength) || !(ly <= kMaxLength))
        fail(GFMD_ERR_FORMAT, "'" + p + "' has an impossible grid: corrupted");
    if (!fits(nx, ny)) fail(GFMD_ERR_NOMEM, "the grid of '" + p + "' does not fit in physical memory");
    const double e_star = r.f64();
    const int32_t kind = r.i32();
    const double width = r.f64(), nu = r.f64(), sigma0 = r.f64(), gamma0 = r.f64(), rho = r.f64();
    const double dt_user = r.f64(), eta_user = r.f64();
    const int32_t solver = r.i32();
    r.i32();  // threads: recorded for information; the loading process keeps its own default
    const int32_t planner = r.i32();
    const double fire_dt = r.f64(), fire_alpha = r.f64();
    const int64_t fire_positive = r.i64();
    if (planner != GFMD_PLANNER_ESTIMATE && planner != GFMD_PLANNER_MEASURE && planner != GFMD_PLANNER_PATIENT)
        fail(GFMD_ERR_FORMAT, "'" + p + "' holds an unknown FFT planner");
    auto s = std::unique_ptr<Simulation>(new Simulation(nx, ny, lx, ly, 0, planner));
    r.array(s->h_.data(), s->n_);
    r.array(s->z_.data(), s->n_);
    r.array(s->v_.data(), s->n_);
    const uint64_t computed = r.hash();
    const uint64_t stored = r.u64();
    if (stored != computed) fail(GFMD_ERR_FORMAT, "'" + p + "' is corrupted: its checksum does not match");
    char extra;
    if (std::fread(&extra, 1, 1, file.f) != 0) fail(GFMD_ERR_FORMAT, "'" + p + "' has data after its end");

    // The checksum guards against damage; the setters also check every value, as for a user's
    // call, so that even a forged file cannot put the simulation in an invalid state.  What they
    // refuse is a property of the file: GFMD_ERR_FORMAT.
    for (int64_t i = 0; i < s->n_; ++i)
        if (!std::isfinite(s->h_[i]) || std::fabs(s->h_[i]) > kMaxHeight || !std::isfinite(s->z_[i]) ||
            !std::isfinite(s->v_[i]) || s->z_[i] < s->h_[i])
            fail(GFMD_ERR_FORMAT, "'" + p + "' holds invalid fields");
    try {
        if (!std::isnan(nu)) s->set_poisson(nu);
        s->set_modulus(e_star);
        s->set_green(kind, width);
        s->set_adhesion(gamma0, rho);
        s->set_pressure(sigma0);
        s->set_timestep(dt_user);
        s->set_damping(eta_user);
        s->set_solver(solver);
    } catch (const Error &e) {
        fail(GFMD_ERR_FORMAT, "'" + p + "' holds invalid parameters: " + e.what());
    }
    if (!(fire_dt >= 0.0) || !(fire_alpha >= 0.0) || fire_positive < 0)
        fail(GFMD_ERR_FORMAT, "'" + p + "' holds an invalid solver state");
    s->fire_dt_ = fire_dt;
    s->fire_alpha_ = fire_alpha;
    s->fire_positive_ = fire_positive;
    s->evaluate_forces();
    return s;
}

}  // namespace gfmd
