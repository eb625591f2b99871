// A checkpoint file shared by the ranks of a distributed grid: MPI-IO, every rank writing and
// reading its own rows at their offsets in the one file (the serial library's layout), the first
// rank the header and the table of row hashes.  Every call ends in an agreement, so an I/O error
// on one rank fails the call on all.
#include <cstdio>
#include <string>

#include "../checkpoint_file.hpp"
#include "../error.hpp"
#include "../fft_grid.hpp"
#include "../fields.hpp"
#include "mpi_state.hpp"

namespace gfmd {

namespace {

class MpiFile final : public CheckpointFile {
public:
    MpiFile(const std::string &path, bool write, MPI_Comm comm) : path_(path), write_(write), comm_(comm) {
        MPI_Comm_rank(comm_, &rank_);
        name_ = write ? path + ".tmp" : path;
        const int amode = write ? (MPI_MODE_CREATE | MPI_MODE_WRONLY) : MPI_MODE_RDONLY;
        const int rc = MPI_File_open(comm_, name_.c_str(), amode, MPI_INFO_NULL, &fh_);
        if (rc != MPI_SUCCESS) fh_ = MPI_FILE_NULL;
        settle(rc == MPI_SUCCESS ? GFMD_OK : GFMD_ERR_IO,
               std::string("cannot ") + (write ? "create '" : "open '") + name_ + "'");
        if (write) settle(MPI_File_set_size(fh_, 0) == MPI_SUCCESS ? GFMD_OK : GFMD_ERR_IO, "cannot write '" + name_ + "'");
    }
    MpiFile(const MpiFile &) = delete;
    MpiFile &operator=(const MpiFile &) = delete;
    ~MpiFile() override {
        if (fh_ != MPI_FILE_NULL) MPI_File_close(&fh_);
        if (write_ && !committed_ && rank_ == 0) std::remove(name_.c_str());
    }
    uint64_t size() override {
        MPI_Offset n = 0;
        settle(MPI_File_get_size(fh_, &n) == MPI_SUCCESS ? GFMD_OK : GFMD_ERR_IO, "cannot read '" + name_ + "'");
        return static_cast<uint64_t>(n);
    }
    void read(uint64_t offset, void *p, std::size_t n) override {
        MPI_Status st;
        int got = 0;
        const bool ok = transfer(offset, n, [&](MPI_Offset at, char *b, int count) {
            return MPI_File_read_at_all(fh_, at, count > 0 ? b : nullptr, count, MPI_BYTE, &st) == MPI_SUCCESS &&
                   MPI_Get_count(&st, MPI_BYTE, &got) == MPI_SUCCESS && got == count;
        }, static_cast<char *>(p));
        settle(ok ? GFMD_OK : GFMD_ERR_FORMAT, "'" + path_ + "' is truncated: not a complete gfmd checkpoint");
    }
    void write(uint64_t offset, const void *p, std::size_t n) override {
        MPI_Status st;
        const bool ok = transfer(offset, n, [&](MPI_Offset at, char *b, int count) {
            return MPI_File_write_at_all(fh_, at, b, count, MPI_BYTE, &st) == MPI_SUCCESS;
        }, const_cast<char *>(static_cast<const char *>(p)));
        settle(ok ? GFMD_OK : GFMD_ERR_IO, "cannot write '" + name_ + "'");
    }
    void commit() override {
        const int rc = MPI_File_close(&fh_);
        fh_ = MPI_FILE_NULL;
        settle(rc == MPI_SUCCESS ? GFMD_OK : GFMD_ERR_IO, "cannot write '" + name_ + "'");
        const bool moved = rank_ != 0 || std::rename(name_.c_str(), path_.c_str()) == 0;
        settle(moved ? GFMD_OK : GFMD_ERR_IO, "cannot write '" + path_ + "'");
        committed_ = true;
    }

private:
    // Collective transfers in pieces below MPI's int count; every rank makes the same number of
    // calls (the largest piece count of any rank), with count 0 when it has nothing left.
    template <class Op>
    bool transfer(uint64_t offset, std::size_t n, Op &&op, char *b) {
        constexpr std::size_t kPiece = std::size_t{1} << 30;
        unsigned long long pieces = (n + kPiece - 1) / kPiece, most = 0;
        if (MPI_Allreduce(&pieces, &most, 1, MPI_UNSIGNED_LONG_LONG, MPI_MAX, comm_) != MPI_SUCCESS) return false;
        bool ok = true;
        for (unsigned long long i = 0; i < most; ++i) {
            const std::size_t done = static_cast<std::size_t>(i) * kPiece;
            const int count = done < n ? static_cast<int>(std::min(kPiece, n - done)) : 0;
            ok = op(static_cast<MPI_Offset>(offset + done), b + (done < n ? done : 0), count) && ok;
        }
        return ok;
    }
    void settle(int32_t status, const std::string &message) {
        std::string m = message;
        const int32_t agreed = agree_on(comm_, status, m);
        if (agreed != GFMD_OK) fail(agreed, m);
    }
    std::string path_, name_;
    bool write_, committed_ = false;
    MPI_Comm comm_;
    int rank_ = 0;
    MPI_File fh_ = MPI_FILE_NULL;
};

}  // namespace

std::unique_ptr<CheckpointFile> open_distributed_checkpoint(const std::string &path, bool write, const Distribution &dist) {
    return std::make_unique<MpiFile>(path, write, dist.comm);
}

}  // namespace gfmd
