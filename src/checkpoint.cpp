// Checkpoint and restart: a simulation's complete state in a portable, versioned binary file.
//
// Format version 4, every number little-endian whatever the machine:
//   "GFMDCKPT"                      8 bytes, magic
//   u32 version = 4, u32 flags = 0 (no flags are defined: others are refused)
//   i64 nx, ny; f64 lx, ly
//   the parameters in the order of GFMD_PARAMS_LIST (params.hpp): f64 e_star; i32 kind;
//     f64 width, nu, sigma0, gamma0, rho, dt_user, eta_user; i32 solver; i32 control; f64 mean_z
//   i32 threads (informative; not restored), planner
//   u32 count, f64 solver_state[count]  (the solver's adaptive state: FIRE's dt, alpha, count)
//   u32 k                               (grid-sized fields of the solver's state: CG's pressure)
//   f64 h[nx*ny], z[nx*ny], v[nx*ny]    (x fastest)
//   f64 field[k][nx*ny]
//   u64 FNV-1a hash of every byte before it
// Version 3 (read, not written) had no k and no solver fields.  Version 2 (read, not written) had no control and mean_z (pressure control).  Version 1 (read)
// also had f64 fire_dt, fire_alpha; i64 fire_positive in place of the solver state.  Readers refuse other magics, versions they do not know, unknown flags, a length
// other than the header implies (before allocating anything), and hash mismatches.
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "error.hpp"
#include "simulation.hpp"

namespace gfmd {

namespace {

constexpr char kMagic[8] = {'G', 'F', 'M', 'D', 'C', 'K', 'P', 'T'};
constexpr uint32_t kVersion = 4;
constexpr uint32_t kMaxSolverFields = 4;  // grid-sized fields of a solver's state; more is a corrupted file
constexpr uint32_t kMaxSolverState = 64;  // numbers of a solver's state; more is a corrupted file

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
    void put(double x) { f64(x); }
    void put(int32_t x) { i32(x); }
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
    void get(double &x) { x = f64(); }
    void get(int32_t &x) { x = i32(); }
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
    // checkpoint under the final name, and a failed save leaves no temporary file behind.
    const std::string tmp = p + ".tmp";
    File file;
    file.f = std::fopen(tmp.c_str(), "wb");
    if (file.f == nullptr) fail(GFMD_ERR_IO, "cannot create '" + tmp + "'");
    try {
        Writer w(file.f, tmp);
        w.bytes(kMagic, 8);
        w.u32(kVersion);
        w.u32(0);
        w.i64(grid_.nx());
        w.i64(grid_.ny());
        w.f64(grid_.lx());
        w.f64(grid_.ly());
#define GFMD_PARAM_WRITE(type, name, value, since) w.put(params_.name);
        GFMD_PARAMS_LIST(GFMD_PARAM_WRITE)
#undef GFMD_PARAM_WRITE
        w.i32(grid_.threads());
        w.i32(grid_.planner());
        const std::vector<double> state = solver_->state();
        w.u32(static_cast<uint32_t>(state.size()));
        for (double x : state) w.f64(x);
        const std::vector<const RealBuffer *> solver_fields = solver_->grid_state();
        w.u32(static_cast<uint32_t>(solver_fields.size()));
        w.array(fields_.h.data(), grid_.local_points());
        w.array(fields_.z.data(), grid_.local_points());
        w.array(fields_.v.data(), grid_.local_points());
        for (const RealBuffer *f : solver_fields) w.array(f->data(), grid_.local_points());
        w.u64(w.hash());
        const bool flushed = std::fflush(file.f) == 0;
        std::FILE *f = std::exchange(file.f, nullptr);
        const bool closed = std::fclose(f) == 0;
        if (!flushed || !closed || std::rename(tmp.c_str(), path) != 0) fail(GFMD_ERR_IO, "cannot write '" + p + "'");
    } catch (...) {
        if (std::FILE *f = std::exchange(file.f, nullptr)) std::fclose(f);
        std::remove(tmp.c_str());
        throw;
    }
}

std::unique_ptr<Simulation> Simulation::load(const char *path) {
    const std::string p(path);
    File file;
    file.f = std::fopen(path, "rb");
    if (file.f == nullptr) fail(GFMD_ERR_IO, "cannot open '" + p + "'");
    if (std::fseek(file.f, 0, SEEK_END) != 0) fail(GFMD_ERR_IO, "cannot read '" + p + "'");
    const long file_size = std::ftell(file.f);
    if (file_size < 0 || std::fseek(file.f, 0, SEEK_SET) != 0) fail(GFMD_ERR_IO, "cannot read '" + p + "'");
    Reader r(file.f, p);
    char magic[8];
    r.bytes(magic, 8);
    if (std::memcmp(magic, kMagic, 8) != 0) fail(GFMD_ERR_FORMAT, "'" + p + "' is not a gfmd checkpoint");
    const uint32_t version = r.u32();
    if (version < 1 || version > kVersion)
        fail(GFMD_ERR_VERSION, "'" + p + "' is a checkpoint of format version " + std::to_string(version) +
                                   "; this library reads versions 1 to " + std::to_string(kVersion));
    const uint32_t flags = r.u32();
    if (flags != 0) fail(GFMD_ERR_FORMAT, "'" + p + "' has unknown flags " + std::to_string(flags) + ": corrupted");
    const int64_t nx = r.i64(), ny = r.i64();
    const double lx = r.f64(), ly = r.f64();
    try {
        validate_grid(nx, ny, lx, ly);
    } catch (const Error &e) {
        fail(GFMD_ERR_FORMAT, "'" + p + "' has an impossible grid: " + e.what());
    }
    Params params;
#define GFMD_PARAM_READ(type, name, value, since) \
    if (version >= (since)) r.get(params.name);
    GFMD_PARAMS_LIST(GFMD_PARAM_READ)
#undef GFMD_PARAM_READ
    r.i32();  // threads: recorded for information; the loading process keeps its own default
    const int32_t planner = r.i32();
    std::vector<double> state;
    if (version == 1) {
        state.push_back(r.f64());
        state.push_back(r.f64());
        state.push_back(static_cast<double>(r.i64()));
    } else {
        const uint32_t count = r.u32();
        if (count > kMaxSolverState) fail(GFMD_ERR_FORMAT, "'" + p + "' holds an impossible solver state: corrupted");
        for (uint32_t i = 0; i < count; ++i) state.push_back(r.f64());
    }
    const uint32_t solver_fields = (version >= 4) ? r.u32() : 0;
    if (solver_fields > kMaxSolverFields) fail(GFMD_ERR_FORMAT, "'" + p + "' holds an impossible solver state: corrupted");
    // The length the header implies, checked before anything is allocated or planned: a small
    // or damaged file that claims a huge grid is refused at once.
    const double fields_bytes = (3.0 + solver_fields) * 8.0 * static_cast<double>(nx) * static_cast<double>(ny);
    const double expected = static_cast<double>(std::ftell(file.f)) + fields_bytes + 8.0;
    if (expected != static_cast<double>(file_size))
        fail(GFMD_ERR_FORMAT, "'" + p + "' has " + std::to_string(file_size) + " bytes; its header (" +
                                  std::to_string(nx) + " x " + std::to_string(ny) + ") implies " +
                                  std::to_string(static_cast<long long>(expected)) + ": truncated or corrupted");
    try {
        validate_planner(planner);
    } catch (const Error &e) {
        fail(GFMD_ERR_FORMAT, "'" + p + "' holds an unknown FFT planner");
    }
    auto s = std::make_unique<Simulation>(nx, ny, lx, ly, 0, planner);
    const int64_t n = s->grid_.local_points();
    Fields &fl = s->fields_;
    r.array(fl.h.data(), n);
    r.array(fl.z.data(), n);
    r.array(fl.v.data(), n);
    std::vector<RealBuffer> extra;
    for (uint32_t k = 0; k < solver_fields; ++k) {
        extra.emplace_back(static_cast<std::size_t>(n));
        r.array(extra.back().data(), n);
    }
    const uint64_t computed = r.hash();
    const uint64_t stored = r.u64();
    if (stored != computed) fail(GFMD_ERR_FORMAT, "'" + p + "' is corrupted: its checksum does not match");

    // The checksum guards against damage; the setters also check every value, as for a user's
    // call, so that even a forged file cannot put the simulation in an invalid state.  What they
    // refuse is a property of the file: GFMD_ERR_FORMAT.
    for (int64_t i = 0; i < n; ++i)
        if (!std::isfinite(fl.h[i]) || std::fabs(fl.h[i]) > kMaxHeight || !std::isfinite(fl.z[i]) ||
            !std::isfinite(fl.v[i]) || fl.z[i] < fl.h[i])
            fail(GFMD_ERR_FORMAT, "'" + p + "' holds invalid fields");
    try {
        if (!std::isnan(params.nu)) s->set_poisson(params.nu);
        s->set_modulus(params.e_star);
        s->set_green(params.kind, params.width);
        s->set_adhesion(params.gamma0, params.rho);
        s->set_pressure(params.sigma0);
        if (params.control == kDisplacementControl) {
            // The saved z already holds its mean: adopted as it is (a new projection could move it
            // by a rounding and the resumed run would differ in the last bits).
            s->check_mean_displacement(params.mean_z, fl.h.data());
            s->params_.control = kDisplacementControl;
            s->params_.mean_z = params.mean_z;
        } else if (params.control != kPressureControl) {
            fail(GFMD_ERR_FORMAT, "unknown load control " + std::to_string(params.control));
        }
        s->set_timestep(params.dt_user);
        s->set_damping(params.eta_user);
        s->set_solver(params.solver);
        s->solver_->set_state(state);
        s->solver_->set_grid_state(std::move(extra));
    } catch (const Error &e) {
        fail(GFMD_ERR_FORMAT, "'" + p + "' holds invalid parameters or solver state: " + e.what());
    }
    s->refresh_forces();
    return s;
}

}  // namespace gfmd
