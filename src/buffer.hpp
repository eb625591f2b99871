// RAII buffers aligned for FFTW (fftw_malloc), zero-initialized.
#ifndef GFMD_SRC_BUFFER_HPP
#define GFMD_SRC_BUFFER_HPP

#include <fftw3.h>

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
        p_ = static_cast<T *>(fftw_malloc(n * sizeof(T)));
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
        if (p_ != nullptr) fftw_free(p_);
        p_ = nullptr;
        n_ = 0;
    }
    T *p_ = nullptr;
    std::size_t n_ = 0;
};

using RealBuffer = AlignedBuffer<double>;
using ComplexBuffer = AlignedBuffer<std::complex<double>>;
using ByteBuffer = AlignedBuffer<unsigned char>;

}  // namespace gfmd

#endif
