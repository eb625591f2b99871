// RAII buffers aligned for FFTW, zero-initialized.  Grid-sized buffers (from 4 MiB) are aligned to
// 2 MiB and offered transparent huge pages (madvise, where the kernel has them in "madvise"
// mode): the transforms' column passes touch one row per page and miss the TLB on 4 KiB pages.
#ifndef GFMD_SRC_BUFFER_HPP
#define GFMD_SRC_BUFFER_HPP

#include <fftw3.h>
#include <stdlib.h>
#if defined(__linux__)
#include <sys/mman.h>
#endif

#include <complex>
#include <cstddef>
#include <cstring>
#include <new>
#include <utility>

namespace gfmd {

template <class T>
class AlignedBuffer {
public:
    AlignedBuffer() = default;
    explicit AlignedBuffer(std::size_t n) : n_(n) {
        if (n == 0) return;
        if (n > static_cast<std::size_t>(-1) / sizeof(T)) throw std::bad_alloc();
        const std::size_t bytes = n * sizeof(T);
        if (huge(n)) {
            void *p = nullptr;
            if (posix_memalign(&p, kHugePage, bytes) != 0) throw std::bad_alloc();
#if defined(__linux__) && defined(MADV_HUGEPAGE)
            (void)madvise(p, bytes, MADV_HUGEPAGE);  // a hint: without it, ordinary pages
#endif
            p_ = static_cast<T *>(p);
        } else {
            p_ = static_cast<T *>(fftw_malloc(bytes));
        }
        if (p_ == nullptr) throw std::bad_alloc();
        std::memset(static_cast<void *>(p_), 0, n * sizeof(T));
    }
    AlignedBuffer(const AlignedBuffer &) = delete;
    AlignedBuffer &operator=(const AlignedBuffer &) = delete;
    AlignedBuffer(AlignedBuffer &&o) noexcept : p_(std::exchange(o.p_, nullptr)), n_(std::exchange(o.n_, 0)) {}
    AlignedBuffer &operator=(AlignedBuffer &&o) noexcept {
        if (this != &o) {
            release();
            p_ = std::exchange(o.p_, nullptr);
            n_ = std::exchange(o.n_, 0);
        }
        return *this;
    }
    ~AlignedBuffer() { release(); }

    T *data() noexcept { return p_; }
    const T *data() const noexcept { return p_; }
    std::size_t size() const noexcept { return n_; }
    T &operator[](std::size_t i) noexcept { return p_[i]; }
    const T &operator[](std::size_t i) const noexcept { return p_[i]; }

private:
    void release() noexcept {
        if (p_ != nullptr) {
            if (huge(n_)) free(p_);
            else fftw_free(p_);
        }
        p_ = nullptr;
        n_ = 0;
    }
    // Which allocator holds a buffer follows from its size alone.
    static constexpr std::size_t kHugePage = std::size_t{2} << 20, kHugeFrom = std::size_t{4} << 20;
    static constexpr bool huge(std::size_t n) noexcept { return n * sizeof(T) >= kHugeFrom; }
    T *p_ = nullptr;
    std::size_t n_ = 0;
};

using RealBuffer = AlignedBuffer<double>;
using ComplexBuffer = AlignedBuffer<std::complex<double>>;
using ByteBuffer = AlignedBuffer<unsigned char>;

}  // namespace gfmd

#endif
