// The distributed grid (libgfmd_mpi): one slab of rows per rank, FFTW's MPI transforms.
//
// FFTW-MPI's transposed layout is the one whose bits do not depend on the number of ranks
// (measured for np = 1..8, ../shared/designs/mpi.md): r2c with TRANSPOSED_OUT leaves kx columns
// of ny modes on each rank.  The library's loops, shared with the serial build, want the slab's
// own ky rows of nxh modes, so an exact FFTW-MPI transpose (data movement only) brings the
// spectrum back to rows after the forward transform and to columns before the backward one.
// The real side is copied into FFTW-MPI's padded rows (2 (nx/2 + 1) doubles) and out again, so
// the library's own arrays stay unpadded (x fastest, rows of nx).  The cost is two more global
// transposes per pair than a column-aware core would need; the bits are the transposed layout's.
#include <algorithm>
#include <climits>
#include <cstring>
#include <memory>
#include <new>
#include <mutex>
#include <string>

#include "../error.hpp"
#include "../fft_grid.hpp"
#include "../fftw_planner.hpp"
#include "../fields.hpp"
#include "mpi_state.hpp"

namespace gfmd {

void check_mpi(int rc, const char *what) {
    if (rc == MPI_SUCCESS) return;
    char text[MPI_MAX_ERROR_STRING];
    int len = 0;
    if (MPI_Error_string(rc, text, &len) != MPI_SUCCESS) len = 0;
    fail(GFMD_ERR_MPI, std::string(what) + " failed: " + std::string(text, static_cast<std::size_t>(len)));
}

namespace {

// FFTW-MPI initialized once per process, after FFTW's threads.  Call with the planner mutex held.
void mpi_ready() {
    static const bool ready = [] {
        threads_ready();
        fftw_mpi_init();
        return true;
    }();
    (void)ready;
}

constexpr ptrdiff_t kMpiBlock = FFTW_MPI_DEFAULT_BLOCK;

}  // namespace

MpiState::~MpiState() {
    destroy_plans();
    if (dist.comm != MPI_COMM_NULL) MPI_Comm_free(&dist.comm);
}

void MpiState::destroy_plans() {
    std::lock_guard<std::mutex> lock(planner_mutex());
    for (fftw_plan *p : {&r2c, &c2r, &to_rows, &to_columns}) {
        if (*p != nullptr) fftw_destroy_plan(*p);
        *p = nullptr;
    }
}

const Distribution *FftGrid::distribution() const { return mpi_ ? &mpi_->dist : nullptr; }

void FftGrid::distribute(const Distribution *dist) {
    auto st = std::make_unique<MpiState>();
    check_mpi(MPI_Comm_dup(dist->comm, &st->dist.comm), "MPI_Comm_dup");
    // Errors of the grid's own communicator come back as codes (GFMD_ERR_MPI), not as an abort.
    check_mpi(MPI_Comm_set_errhandler(st->dist.comm, MPI_ERRORS_RETURN), "MPI_Comm_set_errhandler");
    check_mpi(MPI_Comm_size(st->dist.comm, &ranks_), "MPI_Comm_size");
    check_mpi(MPI_Comm_rank(st->dist.comm, &rank_), "MPI_Comm_rank");
    const ptrdiff_t spectrum[2] = {static_cast<ptrdiff_t>(ny_), static_cast<ptrdiff_t>(nxh())};
    const ptrdiff_t columns[2] = {static_cast<ptrdiff_t>(nxh()), static_cast<ptrdiff_t>(ny_)};
    ptrdiff_t rows = 0, y0 = 0, cols = 0, kx0 = 0, trows = 0, ty0 = 0, tcols = 0, tkx0 = 0;
    ptrdiff_t alloc = 0, talloc = 0;
    {
        std::lock_guard<std::mutex> lock(planner_mutex());
        mpi_ready();
        alloc = fftw_mpi_local_size_many_transposed(2, spectrum, 1, kMpiBlock, kMpiBlock, st->dist.comm, &rows, &y0, &cols, &kx0);
        // The transpose of the spectrum (nxh x ny, two doubles a mode) back to rows.
        talloc = fftw_mpi_local_size_many_transposed(2, columns, 2, kMpiBlock, kMpiBlock, st->dist.comm, &tcols, &tkx0,
                                                     &trows, &ty0);
    }
    if (tcols != cols || tkx0 != kx0 || trows != rows || (rows > 0 && ty0 != y0))
        fail(GFMD_ERR_INTERNAL, "FFTW-MPI's transpose splits the grid unlike its transform");
    local_rows_ = rows;
    first_row_ = rows > 0 ? y0 : std::min<int64_t>(y0, ny_);
    complex_size_ = std::max<int64_t>({alloc, (talloc + 1) / 2, rows * nxh(), 1});
    st->padded = RealBuffer(static_cast<std::size_t>(2 * complex_size_));
    st->columns = ComplexBuffer(static_cast<std::size_t>(complex_size_));
    st->rows_of.assign(static_cast<std::size_t>(ranks_), 0);
    st->first_row_of.assign(static_cast<std::size_t>(ranks_), 0);
    const int mine[2] = {static_cast<int>(local_rows_), static_cast<int>(first_row_)};
    std::vector<int> all(2 * static_cast<std::size_t>(ranks_));
    check_mpi(MPI_Allgather(mine, 2, MPI_INT, all.data(), 2, MPI_INT, st->dist.comm), "MPI_Allgather");
    for (int r = 0; r < ranks_; ++r) {
        st->rows_of[static_cast<std::size_t>(r)] = all[2 * static_cast<std::size_t>(r)];
        st->first_row_of[static_cast<std::size_t>(r)] = all[2 * static_cast<std::size_t>(r) + 1];
    }
    mpi_ = std::move(st);
    replan_distributed(*pool_, planner_);
}

void FftGrid::replan_distributed(ThreadPool &pool, int32_t planner) {
    MpiState &st = *mpi_;
    const ptrdiff_t n[2] = {static_cast<ptrdiff_t>(ny_), static_cast<ptrdiff_t>(nx_)};
    const unsigned flags = planner_flags(planner);
    ComplexBuffer rows(static_cast<std::size_t>(complex_size_));  // a stand-in for the callers' arrays
    auto *cols = reinterpret_cast<fftw_complex *>(st.columns.data());
    fftw_plan made[4] = {nullptr, nullptr, nullptr, nullptr};
    {
        std::lock_guard<std::mutex> lock(planner_mutex());
        // FFTW's threaded MPI plans do not keep the bits of the unthreaded ones (160 x 144 on 2
        // ranks: the energy differs in the last digit, measured), so the reproducible planner
        // transforms on one thread per rank; the library's own loops keep the handle's threads.
        const bool threaded = planner != GFMD_PLANNER_ESTIMATE && real_size() >= kMinPointsForThreads;
        fftw_plan_with_nthreads(threaded ? pool.size() : 1);
        PoolScope scope(&pool);
        WisdomAside aside(planner == GFMD_PLANNER_ESTIMATE);
        made[0] = fftw_mpi_plan_many_dft_r2c(2, n, 1, kMpiBlock, kMpiBlock, st.padded.data(), cols, st.dist.comm,
                                             flags | FFTW_MPI_TRANSPOSED_OUT);
        made[1] = fftw_mpi_plan_many_dft_c2r(2, n, 1, kMpiBlock, kMpiBlock, cols, st.padded.data(), st.dist.comm,
                                             flags | FFTW_MPI_TRANSPOSED_IN);
        made[2] = fftw_mpi_plan_many_transpose(nxh(), ny_, 2, kMpiBlock, kMpiBlock, reinterpret_cast<double *>(cols),
                                               reinterpret_cast<double *>(rows.data()), st.dist.comm, flags);
        made[3] = fftw_mpi_plan_many_transpose(ny_, nxh(), 2, kMpiBlock, kMpiBlock, reinterpret_cast<double *>(rows.data()),
                                               reinterpret_cast<double *>(cols), st.dist.comm, flags);
    }
    // Planning is collective: a rank whose planner failed must not leave the others with plans.
    int ok = (made[0] && made[1] && made[2] && made[3]) ? 1 : 0, all_ok = 0;
    const int rc = MPI_Allreduce(&ok, &all_ok, 1, MPI_INT, MPI_MIN, st.dist.comm);
    if (rc != MPI_SUCCESS || all_ok == 0) {
        std::lock_guard<std::mutex> lock(planner_mutex());
        for (fftw_plan p : made)
            if (p != nullptr) fftw_destroy_plan(p);
        check_mpi(rc, "MPI_Allreduce");
        throw std::bad_alloc();
    }
    st.destroy_plans();
    st.r2c = made[0];
    st.c2r = made[1];
    st.to_rows = made[2];
    st.to_columns = made[3];
}

void FftGrid::forward_distributed(const double *in, std::complex<double> *out) const {
    MpiState &st = *mpi_;
    const int64_t pad = 2 * nxh();
    double *padded = st.padded.data();
    for_mode_rows([&](int64_t r0, int64_t r1) {
        for (int64_t r = r0; r < r1; ++r) std::memcpy(padded + r * pad, in + r * nx_, static_cast<std::size_t>(nx_) * sizeof(double));
    });
    PoolScope scope(pool_.get());
    fftw_mpi_execute_dft_r2c(st.r2c, padded, reinterpret_cast<fftw_complex *>(st.columns.data()));
    fftw_mpi_execute_r2r(st.to_rows, reinterpret_cast<double *>(st.columns.data()), reinterpret_cast<double *>(out));
}

void FftGrid::backward_distributed(std::complex<double> *in, double *out) const {
    MpiState &st = *mpi_;
    PoolScope scope(pool_.get());
    fftw_mpi_execute_r2r(st.to_columns, reinterpret_cast<double *>(in), reinterpret_cast<double *>(st.columns.data()));
    fftw_mpi_execute_dft_c2r(st.c2r, reinterpret_cast<fftw_complex *>(st.columns.data()), st.padded.data());
    const int64_t pad = 2 * nxh();
    const double *padded = st.padded.data();
    for_mode_rows([&](int64_t r0, int64_t r1) {
        for (int64_t r = r0; r < r1; ++r) std::memcpy(out + r * nx_, padded + r * pad, static_cast<std::size_t>(nx_) * sizeof(double));
    });
}

void FftGrid::reduce_exact(ExactSum *x, int k) const {
    if (!mpi_) return;
    // On the stack: sums run every step, and a step allocates nothing.
    constexpr int kMaxSums = 6;  // the most any caller reduces at once (the forces)
    if (k > kMaxSums) fail(GFMD_ERR_INTERNAL, "too many sums in one reduction");
    int64_t words[kMaxSums * ExactSum::kWords];
    for (int i = 0; i < k; ++i) {
        x[i].normalize();
        std::copy(x[i].words(), x[i].words() + ExactSum::kWords, words + i * ExactSum::kWords);
    }
    check_mpi(MPI_Allreduce(MPI_IN_PLACE, words, k * ExactSum::kWords, MPI_INT64_T, MPI_SUM, mpi_->dist.comm),
              "MPI_Allreduce");
    for (int i = 0; i < k; ++i) std::copy(words + i * ExactSum::kWords, words + (i + 1) * ExactSum::kWords, x[i].words());
}

void FftGrid::reduce_max(double *x, int k) const {
    if (!mpi_) return;
    check_mpi(MPI_Allreduce(MPI_IN_PLACE, x, k, MPI_DOUBLE, MPI_MAX, mpi_->dist.comm), "MPI_Allreduce");
}

int32_t FftGrid::agree(int32_t status, std::string &message) const {
    if (!mpi_) return status;
    return agree_on(mpi_->dist.comm, status, message);
}

bool FftGrid::same_on_all_ranks(uint64_t fingerprint) const { return same_everywhere(mpi_->dist.comm, fingerprint); }

bool same_everywhere(MPI_Comm comm, uint64_t fingerprint) noexcept {
    uint64_t v[2] = {fingerprint, ~fingerprint};  // the largest of x and of ~x: x is the same everywhere iff they agree
    if (MPI_Allreduce(MPI_IN_PLACE, v, 2, MPI_UINT64_T, MPI_MAX, comm) != MPI_SUCCESS) return false;
    return v[0] == ~v[1];
}

bool mpi_usable() noexcept {
    int up = 0, down = 0;
    return MPI_Initialized(&up) == MPI_SUCCESS && MPI_Finalized(&down) == MPI_SUCCESS && up && !down;
}

void FftGrid::gather_column0_distributed(const std::complex<double> *local, std::complex<double> *all) const {
    MpiState &st = *mpi_;
    std::vector<std::complex<double>> mine(static_cast<std::size_t>(local_rows_));
    for (int64_t r = 0; r < local_rows_; ++r) mine[static_cast<std::size_t>(r)] = local[r * nxh()];
    check_mpi(MPI_Allgatherv(mine.data(), static_cast<int>(local_rows_), MPI_C_DOUBLE_COMPLEX, all, st.rows_of.data(),
                             st.first_row_of.data(), MPI_C_DOUBLE_COMPLEX, st.dist.comm),
              "MPI_Allgatherv");
}

void FftGrid::gather_rows_distributed(const void *local, std::size_t row_bytes, void *all) const {
    MpiState &st = *mpi_;
    std::vector<int> counts(static_cast<std::size_t>(ranks_)), firsts(static_cast<std::size_t>(ranks_));
    for (int r = 0; r < ranks_; ++r) {
        counts[static_cast<std::size_t>(r)] = st.rows_of[static_cast<std::size_t>(r)] * static_cast<int>(row_bytes);
        firsts[static_cast<std::size_t>(r)] = st.first_row_of[static_cast<std::size_t>(r)] * static_cast<int>(row_bytes);
    }
    check_mpi(MPI_Allgatherv(local, static_cast<int>(local_rows_ * static_cast<int64_t>(row_bytes)), MPI_BYTE, all,
                             counts.data(), firsts.data(), MPI_BYTE, st.dist.comm),
              "MPI_Allgatherv");
}

void FftGrid::send_rows_distributed(const FftGrid &to, const int64_t *dest, const std::complex<double> *rows,
                                    int64_t width, std::complex<double> *out) const {
    const MpiState &mine = *mpi_, &theirs = *to.mpi_;
    // The rank of `to` that owns global row y.
    const auto owner = [&](int64_t y) {
        int r = 0;
        while (r + 1 < ranks_ && !(y >= theirs.first_row_of[static_cast<std::size_t>(r)] &&
                                   y < theirs.first_row_of[static_cast<std::size_t>(r)] + theirs.rows_of[static_cast<std::size_t>(r)]))
            ++r;
        return r;
    };
    // Each row travels as its destination row (exact in a double) and its modes, in row order.
    const int64_t record = 1 + 2 * width;
    std::vector<int> send_count(static_cast<std::size_t>(ranks_), 0), recv_count(send_count), send_at(send_count),
        recv_at(send_count);
    for (int64_t r = 0; r < local_rows_; ++r)
        if (dest[r] >= 0) send_count[static_cast<std::size_t>(owner(dest[r]))] += static_cast<int>(record);
    check_mpi(MPI_Alltoall(send_count.data(), 1, MPI_INT, recv_count.data(), 1, MPI_INT, mine.dist.comm), "MPI_Alltoall");
    int sends = 0, recvs = 0;
    for (int r = 0; r < ranks_; ++r) {
        send_at[static_cast<std::size_t>(r)] = sends;
        recv_at[static_cast<std::size_t>(r)] = recvs;
        sends += send_count[static_cast<std::size_t>(r)];
        recvs += recv_count[static_cast<std::size_t>(r)];
    }
    std::vector<double> send(static_cast<std::size_t>(std::max(sends, 1))), recv(static_cast<std::size_t>(std::max(recvs, 1)));
    std::vector<int> fill(send_at);
    for (int64_t r = 0; r < local_rows_; ++r) {
        if (dest[r] < 0) continue;
        double *p = send.data() + fill[static_cast<std::size_t>(owner(dest[r]))];
        p[0] = static_cast<double>(dest[r]);
        std::memcpy(p + 1, rows + r * width, static_cast<std::size_t>(width) * sizeof(std::complex<double>));
        fill[static_cast<std::size_t>(owner(dest[r]))] += static_cast<int>(record);
    }
    check_mpi(MPI_Alltoallv(send.data(), send_count.data(), send_at.data(), MPI_DOUBLE, recv.data(), recv_count.data(),
                            recv_at.data(), MPI_DOUBLE, mine.dist.comm),
              "MPI_Alltoallv");
    std::fill(out, out + to.complex_size(), std::complex<double>(0.0, 0.0));
    for (int64_t at = 0; at + record <= recvs; at += record) {
        const auto y = static_cast<int64_t>(recv[static_cast<std::size_t>(at)]);
        std::memcpy(static_cast<void *>(out + (y - to.first_row()) * to.nxh()), recv.data() + at + 1,
                    static_cast<std::size_t>(width) * sizeof(std::complex<double>));
    }
}

void check_slab_memory(const Distribution &dist, int64_t nx, int64_t ny) {
    int rank = 0;
    MPI_Comm_rank(dist.comm, &rank);
    int64_t rows = 0, y0 = 0;
    local_slab(dist.comm, nx, ny, rows, y0);
    std::string message;
    int32_t status = GFMD_OK;
    try {
        check_memory(nx, std::max<int64_t>(rows, 1));
        // What MemAvailable does not see (an address-space limit, a cgroup's): the slab's peak
        // bytes asked for, untouched, and given back, before any rank allocates or plans
        const double bytes = kPeakBytesPerPoint * static_cast<double>(nx) * static_cast<double>(std::max<int64_t>(rows, 1));
        std::unique_ptr<unsigned char[]> trial(bytes < 9e18 ? new (std::nothrow) unsigned char[static_cast<std::size_t>(bytes)]
                                                            : nullptr);
        if (!trial)
            fail(GFMD_ERR_NOMEM, "rank " + std::to_string(rank) + ": its slab of " + std::to_string(rows) +
                                     " rows (" + std::to_string(static_cast<long long>(bytes / 1048576.0)) +
                                     " MB at the handle's peak) cannot be allocated");
    } catch (const Error &e) {
        status = e.status();
        message = e.what();
    }
    status = agree_on(dist.comm, status, message);
    if (status != GFMD_OK) fail(status, message);
}

void local_slab(MPI_Comm comm, int64_t nx, int64_t ny, int64_t &local_ny, int64_t &y0) {
    const ptrdiff_t n[2] = {static_cast<ptrdiff_t>(ny), static_cast<ptrdiff_t>(nx / 2 + 1)};
    ptrdiff_t rows = 0, first = 0, cols = 0, kx0 = 0;
    {
        std::lock_guard<std::mutex> lock(planner_mutex());
        mpi_ready();
        fftw_mpi_local_size_many_transposed(2, n, 1, kMpiBlock, kMpiBlock, comm, &rows, &first, &cols, &kx0);
    }
    local_ny = rows;
    y0 = rows > 0 ? first : std::min<int64_t>(first, ny);
}

int32_t agree_on(MPI_Comm comm, int32_t status, std::string &message) noexcept {
    int rank = 0, ranks = 1;
    if (MPI_Comm_rank(comm, &rank) != MPI_SUCCESS || MPI_Comm_size(comm, &ranks) != MPI_SUCCESS) return GFMD_ERR_MPI;
    const int mine = (status != 0) ? rank : ranks;
    int first = ranks;
    if (MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, comm) != MPI_SUCCESS) return GFMD_ERR_MPI;
    if (first == ranks) return 0;
    int32_t agreed = status;
    try {
        int len = static_cast<int>(std::min<std::size_t>(message.size(), 4096));
        if (MPI_Bcast(&agreed, 1, MPI_INT32_T, first, comm) != MPI_SUCCESS ||
            MPI_Bcast(&len, 1, MPI_INT, first, comm) != MPI_SUCCESS)
            return GFMD_ERR_MPI;
        std::string text = (rank == first) ? message.substr(0, static_cast<std::size_t>(len))
                                           : std::string(static_cast<std::size_t>(len), ' ');
        if (MPI_Bcast(&text[0], len, MPI_CHAR, first, comm) != MPI_SUCCESS) return GFMD_ERR_MPI;
        if (rank != first) message = text;
        else message.resize(static_cast<std::size_t>(len));
    } catch (...) {
        // no memory for the message: every rank still has the status
    }
    return agreed;
}

}  // namespace gfmd
