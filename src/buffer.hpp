// RAII buffers aligned for FFTW, zero-initialized.  Grid-sized buffers (from 4 MiB) are aligned to
// 2 MiB and offered transparent huge pages (madvise, where the kernel has them in "madvise"
// mode): the transforms' column passes touch one row per page and miss the TLB on 4 KiB pages.
// On Linux they are anonymous mappings of their own, zero pages from the kernel: a page becomes
// resident only when written, so a buffer a body never uses (the contact pressure of the CG on a
// layer on a fluid foundation, where only its displacement buffer serves as scratch) costs address
// space, not memory.  Not under AddressSanitizer, which checks only the allocator's memory: there
// they come from posix_memalign and are zero-filled, as everywhere else.
#ifndef GFMD_SRC_BUFFER_HPP
#define GFMD_SRC_BUFFER_HPP

#include <fftw3.h>
#include <stdlib.h>
#if defined(__linux__)
#include <sys/mman.h>
#include <unistd.h>
#endif

#include <complex>
#include <cstddef>
#include <cstdint>
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
            p_ = static_cast<T *>(map_huge(bytes));
            return;  // zero pages
        }
        p_ = static_cast<T *>(fftw_malloc(bytes));
        if (p_ == nullptr) throw std::bad_alloc();
        std::memset(static_cast<void *>(p_), 0, bytes);
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
            if (huge(n_)) unmap_huge(p_, n_ * sizeof(T));
            else fftw_free(p_);
        }
        p_ = nullptr;
        n_ = 0;
    }
    // Which allocator holds a buffer follows from its size alone.
    static constexpr std::size_t kHugePage = std::size_t{2} << 20, kHugeFrom = std::size_t{4} << 20;
#if defined(__linux__) && !defined(__SANITIZE_ADDRESS__)
    static std::size_t mapped(std::size_t bytes) noexcept {  // whole pages (4 KiB, or 64 KiB on some targets)
        const long page = sysconf(_SC_PAGESIZE);
        const std::size_t p = page > 0 ? static_cast<std::size_t>(page) : 4096;
        return (bytes + p - 1) / p * p;
    }
    // bytes zero-filled, 2 MiB aligned: a mapping 2 MiB longer, trimmed at both ends
    static void *map_huge(std::size_t bytes) {
        const std::size_t len = mapped(bytes);
        if (len > static_cast<std::size_t>(-1) - kHugePage) throw std::bad_alloc();
        void *raw = mmap(nullptr, len + kHugePage, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
        if (raw == MAP_FAILED) throw std::bad_alloc();
        const auto r = reinterpret_cast<std::uintptr_t>(raw);
        const std::uintptr_t a = (r + kHugePage - 1) & ~(std::uintptr_t{kHugePage} - 1);
        const std::size_t head = a - r, tail = kHugePage - head;
        if (head > 0) (void)munmap(raw, head);
        if (tail > 0) (void)munmap(reinterpret_cast<void *>(a + len), tail);
#if defined(MADV_HUGEPAGE)
        (void)madvise(reinterpret_cast<void *>(a), len, MADV_HUGEPAGE);  // a hint: without it, ordinary pages
#endif
        return reinterpret_cast<void *>(a);
    }
    static void unmap_huge(void *p, std::size_t bytes) noexcept { (void)munmap(p, mapped(bytes)); }
#else
    static void *map_huge(std::size_t bytes) {
        void *p = nullptr;
        if (posix_memalign(&p, kHugePage, bytes) != 0) throw std::bad_alloc();
        std::memset(p, 0, bytes);
        return p;
    }
    static void unmap_huge(void *p, std::size_t) noexcept { free(p); }
#endif
    static constexpr bool huge(std::size_t n) noexcept { return n * sizeof(T) >= kHugeFrom; }
    T *p_ = nullptr;
    std::size_t n_ = 0;
};

using RealBuffer = AlignedBuffer<double>;
using ComplexBuffer = AlignedBuffer<std::complex<double>>;
using ByteBuffer = AlignedBuffer<unsigned char>;

}  // namespace gfmd

#endif
