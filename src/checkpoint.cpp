// Checkpoint and restart: a simulation's complete state in a portable, versioned binary file.
//
// Format version 7, every number little-endian whatever the machine:
//   "GFMDCKPT"                      8 bytes, magic
//   u32 version = 7, u32 flags = 0 (no flags are defined: others are refused)
//   i64 nx, ny; f64 lx, ly             (the grid solved on: with free boundaries the padded cell)
//   the parameters in the order of GFMD_PARAMS_LIST (params.hpp): f64 e_star; i32 kind;
//     f64 width, nu, sigma0, gamma0, rho, dt_user, eta_user; i32 solver; i32 control; f64 mean_z;
//     f64 hardness; i32 boundary
//   i32 threads (informative; not restored), planner
//   i32 active                          (the solver that steps: AUTO's choice, or the solver set)
//   u32 count, f64 solver_state[count]  (the solver's adaptive state: FIRE's dt, alpha, count)
//   u32 k                               (grid-sized fields of the solver's state: CG's pressure)
//   u32 m, f64 plastic_volume           (m = 1 with a finite hardness: the load step's substrate)
//   f64 h[nx*ny], z[nx*ny], v[nx*ny]    (x fastest)
//   f64 field[k][nx*ny], f64 substrate[m][nx*ny]
//   u64 row_hash[3 + k + m][ny]         FNV-1a of each row's 8 nx bytes, field by field
//   u64 FNV-1a hash of the header (every byte before the fields) and then of the row hashes
// The row hashes let every rank of a distributed grid check and hash its own rows: the table and
// the file do not depend on how many ranks wrote it, and any number of ranks (or the serial
// library) reads it.  Version 6 had no boundary (periodic).  Version 5 had no hardness, m and plastic volume.  Version 4 (read, not written) had no active solver and no row hashes: its
// last 8 bytes hash every byte before them; with solver = AUTO, k > 0 says AUTO had chosen CG
// (its only choices then were CG and FIRE).  Version 3 also had no k and no solver fields.  Version 2 had no control and
// mean_z (pressure control).  Version 1 also had f64 fire_dt, fire_alpha; i64 fire_positive in
// place of the solver state.  Readers refuse other magics, versions they do not know, unknown
// flags, a length other than the header implies (before allocating anything), and hash mismatches.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "checkpoint_file.hpp"
#include "error.hpp"
#include "simulation.hpp"
#ifdef GFMD_MPI
#include "mpi/mpi_state.hpp"
#endif

namespace gfmd {

namespace {

constexpr char kMagic[8] = {'G', 'F', 'M', 'D', 'C', 'K', 'P', 'T'};
constexpr uint32_t kVersion = 7;
constexpr uint32_t kMaxSolverFields = 4;  // grid-sized fields of a solver's state; more is a corrupted file
constexpr uint32_t kMaxSolverState = 64;  // numbers of a solver's state; more is a corrupted file
constexpr std::size_t kMaxHeader = 4096;  // no header of any version is longer
constexpr uint64_t kFnvStart = 0xcbf29ce484222325ULL;

uint64_t fnv(uint64_t h, const unsigned char *b, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) h = (h ^ b[i]) * 0x100000001b3ULL;
    return h;
}

void put_le(uint64_t x, unsigned char *b) {
    for (int i = 0; i < 8; ++i) b[i] = static_cast<unsigned char>(x >> (8 * i));
}

uint64_t get_le(const unsigned char *b) {
    uint64_t x = 0;
    for (int i = 0; i < 8; ++i) x |= static_cast<uint64_t>(b[i]) << (8 * i);
    return x;
}

// The header, little-endian, in memory.
class HeaderWriter {
public:
    void bytes(const void *p, std::size_t n) {
        const auto *b = static_cast<const unsigned char *>(p);
        out.insert(out.end(), b, b + n);
    }
    void u64(uint64_t x) {
        unsigned char b[8];
        put_le(x, b);
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
    std::vector<unsigned char> out;
};

// A header in memory; running past its end means the file is truncated.
class HeaderReader {
public:
    HeaderReader(const unsigned char *b, std::size_t n, const std::string &path) : b_(b), n_(n), path_(path) {}
    void bytes(void *p, std::size_t n) {
        if (n > n_ - at_) fail(GFMD_ERR_FORMAT, "'" + path_ + "' is truncated: not a complete gfmd checkpoint");
        std::memcpy(p, b_ + at_, n);
        at_ += n;
    }
    uint64_t u64() {
        unsigned char b[8];
        bytes(b, 8);
        return get_le(b);
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
    std::size_t position() const { return at_; }

private:
    const unsigned char *b_;
    std::size_t n_, at_ = 0;
    std::string path_;
};

struct Header {
    uint32_t version = 0;
    int64_t nx = 0, ny = 0;
    double lx = 0.0, ly = 0.0;
    Params params;
    int32_t planner = 0;
    int32_t active = -1;  // format 5; -1 before
    std::vector<double> state;
    uint32_t solver_fields = 0;
    uint32_t plastic_fields = 0;  // format 6
    double plastic_volume = 0.0;
    std::size_t length = 0;  // bytes before the fields
};

Header parse_header(const unsigned char *b, std::size_t n, const std::string &p) {
    HeaderReader r(b, n, p);
    Header hd;
    char magic[8];
    r.bytes(magic, 8);
    if (std::memcmp(magic, kMagic, 8) != 0) fail(GFMD_ERR_FORMAT, "'" + p + "' is not a gfmd checkpoint");
    hd.version = r.u32();
    if (hd.version < 1 || hd.version > kVersion)
        fail(GFMD_ERR_VERSION, "'" + p + "' is a checkpoint of format version " + std::to_string(hd.version) +
                                   "; this library reads versions 1 to " + std::to_string(kVersion));
    const uint32_t flags = r.u32();
    if (flags != 0) fail(GFMD_ERR_FORMAT, "'" + p + "' has unknown flags " + std::to_string(flags) + ": corrupted");
    hd.nx = r.i64();
    hd.ny = r.i64();
    hd.lx = r.f64();
    hd.ly = r.f64();
    try {
        validate_grid(hd.nx, hd.ny, hd.lx, hd.ly);
    } catch (const Error &e) {
        fail(GFMD_ERR_FORMAT, "'" + p + "' has an impossible grid: " + e.what());
    }
#define GFMD_PARAM_READ(type, name, value, since) \
    if (hd.version >= (since)) r.get(hd.params.name);
    GFMD_PARAMS_LIST(GFMD_PARAM_READ)
#undef GFMD_PARAM_READ
    r.i32();  // threads: recorded for information; the loading process keeps its own default
    hd.planner = r.i32();
    if (hd.version >= 5) hd.active = r.i32();
    if (hd.version == 1) {
        hd.state.push_back(r.f64());
        hd.state.push_back(r.f64());
        hd.state.push_back(static_cast<double>(r.i64()));
    } else {
        const uint32_t count = r.u32();
        if (count > kMaxSolverState) fail(GFMD_ERR_FORMAT, "'" + p + "' holds an impossible solver state: corrupted");
        for (uint32_t i = 0; i < count; ++i) hd.state.push_back(r.f64());
    }
    hd.solver_fields = (hd.version >= 4) ? r.u32() : 0;
    if (hd.solver_fields > kMaxSolverFields) fail(GFMD_ERR_FORMAT, "'" + p + "' holds an impossible solver state: corrupted");
    if (hd.version >= 6) {
        hd.plastic_fields = r.u32();
        hd.plastic_volume = r.f64();
        if (hd.plastic_fields > 1 || !(hd.params.hardness > 0.0) || (hd.plastic_fields == 1) != std::isfinite(hd.params.hardness) ||
            !(hd.plastic_volume >= 0.0) || !std::isfinite(hd.plastic_volume))
            fail(GFMD_ERR_FORMAT, "'" + p + "' holds an impossible plastic state: corrupted");
    }
    const int32_t bound = hd.params.boundary;
    if ((bound != GFMD_BOUNDARY_PERIODIC && bound != GFMD_BOUNDARY_FREE) ||
        (bound == GFMD_BOUNDARY_FREE && (hd.nx % 2 != 0 || hd.ny % 2 != 0)))
        fail(GFMD_ERR_FORMAT, "'" + p + "' holds an impossible boundary: corrupted");
    hd.length = r.position();
    return hd;
}

// Rows [0, rows) of a field of nx columns to little-endian bytes, and the FNV-1a hash of each row.
void encode_rows(const double *a, int64_t nx, int64_t rows, unsigned char *out, uint64_t *hashes) {
    for (int64_t r = 0; r < rows; ++r) {
        unsigned char *row = out + 8 * nx * r;
        for (int64_t i = 0; i < nx; ++i) {
            uint64_t u;
            std::memcpy(&u, &a[r * nx + i], 8);
            put_le(u, row + 8 * i);
        }
        hashes[r] = fnv(kFnvStart, row, static_cast<std::size_t>(8 * nx));
    }
}

void decode_rows(const unsigned char *in, int64_t nx, int64_t rows, double *a, uint64_t *hashes) {
    for (int64_t r = 0; r < rows; ++r) {
        const unsigned char *row = in + 8 * nx * r;
        for (int64_t i = 0; i < nx; ++i) {
            const uint64_t u = get_le(row + 8 * i);
            std::memcpy(&a[r * nx + i], &u, 8);
        }
        hashes[r] = fnv(kFnvStart, row, static_cast<std::size_t>(8 * nx));
    }
}

// The serial file: stdio.
class SerialFile final : public CheckpointFile {
public:
    SerialFile(const std::string &path, bool write) : path_(path), name_(write ? path + ".tmp" : path), write_(write) {
        f_ = std::fopen(name_.c_str(), write ? "wb" : "rb");
        if (f_ == nullptr) fail(GFMD_ERR_IO, std::string("cannot ") + (write ? "create '" : "open '") + name_ + "'");
    }
    SerialFile(const SerialFile &) = delete;
    SerialFile &operator=(const SerialFile &) = delete;
    ~SerialFile() override {
        if (f_ != nullptr) std::fclose(f_);
        if (write_ && !committed_) std::remove(name_.c_str());
    }
    uint64_t size() override {
        if (std::fseek(f_, 0, SEEK_END) != 0) fail(GFMD_ERR_IO, "cannot read '" + name_ + "'");
        const long n = std::ftell(f_);
        if (n < 0) fail(GFMD_ERR_IO, "cannot read '" + name_ + "'");
        return static_cast<uint64_t>(n);
    }
    void read(uint64_t offset, void *p, std::size_t n) override {
        if (n == 0) return;
        if (std::fseek(f_, static_cast<long>(offset), SEEK_SET) != 0 || std::fread(p, 1, n, f_) != n)
            fail(GFMD_ERR_FORMAT, "'" + path_ + "' is truncated: not a complete gfmd checkpoint");
    }
    void write(uint64_t offset, const void *p, std::size_t n) override {
        if (n == 0) return;
        if (std::fseek(f_, static_cast<long>(offset), SEEK_SET) != 0 || std::fwrite(p, 1, n, f_) != n)
            fail(GFMD_ERR_IO, "cannot write '" + name_ + "'");
    }
    void commit() override {
        const bool flushed = std::fflush(f_) == 0;
        const bool closed = std::fclose(std::exchange(f_, nullptr)) == 0;
        if (!flushed || !closed || std::rename(name_.c_str(), path_.c_str()) != 0)
            fail(GFMD_ERR_IO, "cannot write '" + path_ + "'");
        committed_ = true;
    }

private:
    std::string path_, name_;
    bool write_, committed_ = false;
    std::FILE *f_ = nullptr;
};

}  // namespace

std::unique_ptr<CheckpointFile> open_checkpoint(const std::string &path, bool write, const Distribution *dist) {
#ifdef GFMD_MPI
    if (dist != nullptr) return open_distributed_checkpoint(path, write, *dist);
#endif
    (void)dist;
    return std::make_unique<SerialFile>(path, write);
}

void Simulation::save(const char *path) const {
    HeaderWriter w;
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
    w.i32(active_solver_);
    const std::vector<double> state = solver_->state();
    w.u32(static_cast<uint32_t>(state.size()));
    for (double x : state) w.f64(x);
    std::vector<const double *> fields = {fields_.h.data(), fields_.z.data(), fields_.v.data()};
    for (const RealBuffer *f : solver_->grid_state()) fields.push_back(f->data());
    w.u32(static_cast<uint32_t>(fields.size() - 3));
    w.u32(plastic_ ? 1 : 0);
    w.f64(plastic_ ? plastic_->committed_volume : 0.0);
    if (plastic_) fields.push_back(plastic_->substrate.data());

    // Written to "<path>.tmp" and renamed: a crash while saving never leaves a damaged checkpoint
    // under the final name, and a failed save leaves no temporary file behind.
    const int64_t nx = grid_.nx(), ny = grid_.ny(), rows = grid_.local_mode_rows(), y0 = grid_.first_row();
    const uint64_t field_bytes = 8 * static_cast<uint64_t>(nx) * static_cast<uint64_t>(ny);
    std::vector<unsigned char> bytes;
    std::vector<uint64_t> mine, table;
    grid_.on_all_ranks([&] {  // the buffers on every rank or on none, before the collective open
        bytes.resize(static_cast<std::size_t>(8 * nx * rows));
        mine.resize(static_cast<std::size_t>(rows));
        table.resize(fields.size() * static_cast<std::size_t>(ny));
    });
    auto file = open_checkpoint(path, true, grid_.distribution());
    const bool first = grid_.rank() == 0;
    file->write(0, w.out.data(), first ? w.out.size() : 0);
    for (std::size_t k = 0; k < fields.size(); ++k) {
        encode_rows(fields[k], nx, rows, bytes.data(), mine.data());
        file->write(w.out.size() + k * field_bytes + 8 * static_cast<uint64_t>(nx * y0), bytes.data(), bytes.size());
        grid_.gather_rows(mine.data(), sizeof(uint64_t), table.data() + k * static_cast<std::size_t>(ny));
    }
    std::vector<unsigned char> tail(8 * table.size() + 8);
    for (std::size_t i = 0; i < table.size(); ++i) put_le(table[i], tail.data() + 8 * i);
    put_le(fnv(fnv(kFnvStart, w.out.data(), w.out.size()), tail.data(), 8 * table.size()), tail.data() + 8 * table.size());
    file->write(w.out.size() + fields.size() * field_bytes, tail.data(), first ? tail.size() : 0);
    file->commit();
}

std::unique_ptr<Simulation> Simulation::load(const char *path, const Distribution *dist) {
    const std::string p(path);
#ifdef GFMD_MPI
    if (dist != nullptr) {
        // Every rank reads the header by itself and checks that its slab fits before the collective
        // MPI-IO open: a rank short of memory fails in the open of some MPI libraries and leaves the
        // others waiting in it (Open MPI's shared file pointer, measured with a squeezed rank).
        std::string message;
        int32_t status = GFMD_OK;
        Header pre;
        try {
            SerialFile f(p, false);
            std::vector<unsigned char> b(static_cast<std::size_t>(std::min<uint64_t>(f.size(), kMaxHeader)));
            f.read(0, b.data(), b.size());
            pre = parse_header(b.data(), b.size(), p);
        } catch (const Error &e) {
            status = e.status();
            message = e.what();
        } catch (const std::bad_alloc &) {
            status = GFMD_ERR_NOMEM;
            message = "out of memory";
        }
        status = agree_on(dist->comm, status, message);
        if (status != GFMD_OK) fail(status, message);
        check_slab_memory(*dist, pre.nx, pre.ny);
    }
#endif
    auto file = open_checkpoint(p, false, dist);
    const uint64_t file_size = file->size();
    std::vector<unsigned char> head(static_cast<std::size_t>(std::min<uint64_t>(file_size, kMaxHeader)));
    file->read(0, head.data(), head.size());
    const Header hd = parse_header(head.data(), head.size(), p);
    const int64_t nx = hd.nx, ny = hd.ny;
    const std::size_t nfields = 3 + hd.solver_fields + hd.plastic_fields;
    // The length the header implies, checked before anything is allocated or planned: a small
    // or damaged file that claims a huge grid is refused at once.
    const double field_bytes = 8.0 * static_cast<double>(nx) * static_cast<double>(ny);
    const double table_bytes = (hd.version >= 5) ? 8.0 * static_cast<double>(nfields) * static_cast<double>(ny) : 0.0;
    const double expected = static_cast<double>(hd.length) + static_cast<double>(nfields) * field_bytes + table_bytes + 8.0;
    if (expected != static_cast<double>(file_size))
        fail(GFMD_ERR_FORMAT, "'" + p + "' has " + std::to_string(file_size) + " bytes; its header (" +
                                  std::to_string(nx) + " x " + std::to_string(ny) + ") implies " +
                                  std::to_string(static_cast<long long>(expected)) + ": truncated or corrupted");
    try {
        validate_planner(hd.planner);
    } catch (const Error &e) {
        fail(GFMD_ERR_FORMAT, "'" + p + "' holds an unknown FFT planner");
    }
    if (dist == nullptr) check_memory(nx, ny);
#ifdef GFMD_MPI
    else check_slab_memory(*dist, nx, ny);
#endif
    // free boundaries: the file holds the padded cell, twice the region each way
    const int64_t half = (hd.params.boundary == GFMD_BOUNDARY_FREE) ? 2 : 1;
    auto s = std::make_unique<Simulation>(nx / half, ny / half, hd.lx / static_cast<double>(half),
                                          hd.ly / static_cast<double>(half), 0, hd.planner, dist, hd.params.boundary);
    const FftGrid &g = s->grid_;
    const int64_t rows = g.local_mode_rows(), y0 = g.first_row();
    Fields &fl = s->fields_;
    std::vector<RealBuffer> extra;
    std::vector<double *> targets = {fl.h.data(), fl.z.data(), fl.v.data()};
    RealBuffer substrate;
    std::vector<unsigned char> bytes;
    std::vector<uint64_t> mine;
    g.on_all_ranks([&] {  // on every rank or on none: no rank waits in a read
        for (uint32_t k = 0; k < hd.solver_fields; ++k) {
            extra.emplace_back(static_cast<std::size_t>(g.local_points()));
            targets.push_back(extra.back().data());
        }
        if (hd.plastic_fields > 0) {
            substrate = RealBuffer(static_cast<std::size_t>(g.local_points()));
            targets.push_back(substrate.data());
        }
        bytes.resize(static_cast<std::size_t>(8 * nx * rows));
        mine.resize(nfields * static_cast<std::size_t>(rows));
    });
    for (std::size_t k = 0; k < nfields; ++k) {
        file->read(hd.length + static_cast<uint64_t>(k * field_bytes) + 8 * static_cast<uint64_t>(nx * y0), bytes.data(),
                   bytes.size());
        decode_rows(bytes.data(), nx, rows, targets[k], mine.data() + k * static_cast<std::size_t>(rows));
    }
    const uint64_t end = file_size - 8;
    if (hd.version >= 5) {
        // Every rank checks its own rows against the table, and the table against the final hash.
        std::vector<unsigned char> tail(static_cast<std::size_t>(table_bytes) + 8);
        file->read(hd.length + static_cast<uint64_t>(nfields * field_bytes), tail.data(), tail.size());
        const uint64_t computed = fnv(fnv(kFnvStart, head.data(), hd.length), tail.data(), tail.size() - 8);
        bool rows_match = true;
        for (std::size_t k = 0; k < nfields; ++k)
            for (int64_t r = 0; r < rows; ++r)
                rows_match = rows_match && get_le(tail.data() + 8 * (k * static_cast<std::size_t>(ny) + static_cast<std::size_t>(y0 + r))) ==
                                               mine[k * static_cast<std::size_t>(rows) + static_cast<std::size_t>(r)];
        g.on_all_ranks([&] {
            if (computed != get_le(tail.data() + tail.size() - 8) || !rows_match)
                fail(GFMD_ERR_FORMAT, "'" + p + "' is corrupted: its checksum does not match");
        });
    } else {
        // One hash over every byte before the last 8: formed by the first rank, in chunks.
        uint64_t h = kFnvStart;
        std::vector<unsigned char> chunk(1 << 20);
        const bool first = g.rank() == 0;
        for (uint64_t at = 0; at < end; at += chunk.size()) {
            const std::size_t n = static_cast<std::size_t>(std::min<uint64_t>(chunk.size(), end - at));
            file->read(at, chunk.data(), first ? n : 0);
            if (first) h = fnv(h, chunk.data(), n);
        }
        unsigned char stored[8];
        file->read(end, stored, first ? 8 : 0);
        g.on_all_ranks([&] {
            if (first && h != get_le(stored)) fail(GFMD_ERR_FORMAT, "'" + p + "' is corrupted: its checksum does not match");
        });
    }

    // The checksum guards against damage; the setters also check every value, as for a user's
    // call, so that even a forged file cannot put the simulation in an invalid state.  What they
    // refuse is a property of the file: GFMD_ERR_FORMAT.
    const int64_t n = g.local_points();
    g.on_all_ranks([&] {
        for (int64_t i = 0; i < n; ++i)
            if (!std::isfinite(fl.h[i]) || std::fabs(fl.h[i]) > kMaxHeight || !std::isfinite(fl.z[i]) ||
                !std::isfinite(fl.v[i]) || fl.z[i] < fl.h[i])
                fail(GFMD_ERR_FORMAT, "'" + p + "' holds invalid fields");
    });
    const Params &params = hd.params;
    try {
        if (!std::isnan(params.nu)) s->set_poisson(params.nu);
        s->set_modulus(params.e_star);
        s->set_green(params.kind, params.width);
        s->set_adhesion(params.gamma0, params.rho);
        s->set_pressure(params.sigma0 / s->load_fraction());
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
        if (params.solver == GFMD_SOLVER_AUTO) {
            // The choice AUTO made when the load was set, not the one the loaded state would give
            // now.  Format 4 did not record it: its AUTO chose CG (a grid-sized field of state) or FIRE.
            int32_t active = hd.active;
            if (hd.version < 5) active = (hd.solver_fields > 0) ? GFMD_SOLVER_CG : GFMD_SOLVER_FIRE;
            if (active == GFMD_SOLVER_AUTO) fail(GFMD_ERR_INVALID_ARG, "AUTO is not a solver that steps");
            s->set_solver(active);  // the checks of a user's choice (CG and adhesion)
            s->params_.solver = GFMD_SOLVER_AUTO;
        } else if (hd.version >= 5 && hd.active != params.solver) {
            fail(GFMD_ERR_INVALID_ARG, "the solver that steps is not the solver set");
        }
        if (std::isfinite(params.hardness)) {
            s->set_hardness(params.hardness);
            for (int64_t i = 0; i < n; ++i)
                if (!std::isfinite(substrate[i]) || substrate[i] < fl.h[i] || std::fabs(substrate[i]) > kMaxHeight)
                    fail(GFMD_ERR_FORMAT, "invalid plastic substrate");
            std::swap(s->plastic_->substrate, substrate);
            s->plastic_->committed_volume = hd.plastic_volume;
        }
        s->solver_->set_state(hd.state);
        s->solver_->set_grid_state(std::move(extra));
    } catch (const Error &e) {
        fail(GFMD_ERR_FORMAT, "'" + p + "' holds invalid parameters or solver state: " + e.what());
    }
    s->refresh_forces();
    return s;
}

}  // namespace gfmd
