// Exact summation of doubles (a "superaccumulator": Kulisch's long accumulator in 32-bit digits).
// The distributed grid forms one partial sum per global row and adds the partials here exactly,
// then adds the accumulators of all ranks as integers: the rounded result is the same bits for any
// decomposition of the rows over ranks and threads, since integer addition does not depend on order.
#ifndef GFMD_SRC_EXACT_SUM_HPP
#define GFMD_SRC_EXACT_SUM_HPP

#include <cmath>
#include <cstdint>
#include <limits>

namespace gfmd {

class ExactSum {
public:
    // Digit i weighs 2^(32 i - kBias): bit 0 is below the smallest subnormal's mantissa (2^-1074 =
    // 2^-1126 x 2^52 for frexp's 53-bit integer mantissa), the top digits leave room for carries.
    static constexpr int kDigits = 72;
    static constexpr int kBias = 1127;
    // The words an Allreduce adds: the digits, then the counts of NaN, +inf and -inf terms.
    static constexpr int kWords = kDigits + 3;

    void add(double x) {
        if (!std::isfinite(x)) {
            if (std::isnan(x)) ++w_[kDigits];
            else ++w_[x > 0 ? kDigits + 1 : kDigits + 2];
            return;
        }
        if (x == 0.0) return;
        int e = 0;
        const double frac = std::frexp(x, &e);                      // x = frac 2^e, 0.5 <= |frac| < 1
        const auto m = static_cast<int64_t>(std::ldexp(frac, 53));  // exact: |m| < 2^53
        const int p = e - 53 + kBias;                                // bit position of m's lowest bit
        // |m| shifted by s < 32 spans at most 85 bits: three 32-bit chunks (bits 64+ from u >> (64 - s)).
        const uint64_t u = static_cast<uint64_t>(m < 0 ? -m : m), shifted = u << (p % 32);
        const int s = p % 32;
        const int64_t sign = m < 0 ? -1 : 1;
        const int d = p / 32;
        w_[d] += sign * static_cast<int64_t>(shifted & 0xffffffffu);
        w_[d + 1] += sign * static_cast<int64_t>(shifted >> 32);
        w_[d + 2] += sign * static_cast<int64_t>(s == 0 ? 0 : u >> (64 - s));
        if (++adds_ == (int64_t{1} << 30)) normalize();  // each add moves a digit by < 2^32
    }

    // Carries propagated: digits 0 .. kDigits-2 in [0, 2^32), the top one signed.  Call before
    // adding accumulators as integers (the sum of a few normalized ones cannot overflow).
    void normalize() {
        for (int i = 0; i + 1 < kDigits; ++i) {
            const int64_t carry = w_[i] >> 32;  // floor division by 2^32
            w_[i] -= carry * (int64_t{1} << 32);
            w_[i + 1] += carry;
        }
        adds_ = 0;
    }

    void merge(const ExactSum &o) {
        for (int i = 0; i < kWords; ++i) w_[i] += o.w_[i];
    }

    int64_t *words() { return w_; }

    // The sum rounded to a double (IEEE rules for inf and NaN terms).  Deterministic: the same
    // exact value always gives the same double.
    double value() const {
        if (w_[kDigits] > 0 || (w_[kDigits + 1] > 0 && w_[kDigits + 2] > 0)) return std::numeric_limits<double>::quiet_NaN();
        if (w_[kDigits + 1] > 0) return std::numeric_limits<double>::infinity();
        if (w_[kDigits + 2] > 0) return -std::numeric_limits<double>::infinity();
        ExactSum t = *this;
        t.normalize();
        double sign = 1.0;
        if (t.w_[kDigits - 1] < 0) {  // negative: take the magnitude
            for (int i = 0; i < kDigits; ++i) t.w_[i] = -t.w_[i];
            t.normalize();
            sign = -1.0;
        }
        int top = kDigits - 1;
        while (top >= 0 && t.w_[top] == 0) --top;
        if (top < 0) return 0.0;
        // The top 96 bits carry the value to well below half an ulp; lower digits only decide
        // rounding ties, which the sticky bit breaks toward the magnitude.
        const int lo = top >= 2 ? top - 2 : 0;
        bool sticky = false;
        for (int i = 0; i < lo; ++i) sticky = sticky || t.w_[i] != 0;
        const uint64_t hi = (static_cast<uint64_t>(t.w_[top]) << 32) | static_cast<uint64_t>(top >= 1 ? t.w_[top - 1] : 0);
        const uint64_t low = static_cast<uint64_t>(top >= 2 ? t.w_[top - 2] : 0) | (sticky ? 1u : 0u);
        const int shift = 32 * (top - 1) - kBias;
        return sign * (std::ldexp(static_cast<double>(hi), shift) + std::ldexp(static_cast<double>(low), shift - 32));
    }

private:
    int64_t w_[kWords] = {};
    int64_t adds_ = 0;
};

}  // namespace gfmd

#endif
