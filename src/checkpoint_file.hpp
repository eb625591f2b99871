// The file under a checkpoint: one file, written and read by every rank of a grid at once.  The
// serial library reads and writes it with stdio; libgfmd_mpi with MPI-IO (src/mpi/).  Every call
// is collective on a distributed grid (a rank with nothing to move passes n = 0) and fails on
// every rank alike.
#ifndef GFMD_SRC_CHECKPOINT_FILE_HPP
#define GFMD_SRC_CHECKPOINT_FILE_HPP

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

namespace gfmd {

struct Distribution;

class CheckpointFile {
public:
    virtual ~CheckpointFile() = default;
    virtual uint64_t size() = 0;
    // Reads n bytes at offset (n = 0: nothing, still collective); GFMD_ERR_FORMAT past the end.
    virtual void read(uint64_t offset, void *p, std::size_t n) = 0;
    // Writes n bytes at offset; GFMD_ERR_IO if it cannot.
    virtual void write(uint64_t offset, const void *p, std::size_t n) = 0;
    // A file opened for writing goes to its final name (written to "<path>.tmp" until then); a
    // file dropped without commit() leaves nothing behind.
    virtual void commit() = 0;
};

// dist = nullptr: a serial file; otherwise one shared by the distribution's ranks.
std::unique_ptr<CheckpointFile> open_checkpoint(const std::string &path, bool write, const Distribution *dist);
#ifdef GFMD_MPI
std::unique_ptr<CheckpointFile> open_distributed_checkpoint(const std::string &path, bool write, const Distribution &dist);
#endif

}  // namespace gfmd

#endif
