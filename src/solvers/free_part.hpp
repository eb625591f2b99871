// v at a free point, +0 at a held one: the same value as `held ? 0 : v`, by masking v's bits.
// Written as that select, GCC 12 sinks v's computation into the branch that uses it, its loads
// become conditional and a loop over the points stays scalar ("control flow in loop" in
// -fopt-info-vec); masked, v is needed at every point and the loop vectorizes.
#ifndef GFMD_SRC_SOLVERS_FREE_PART_HPP
#define GFMD_SRC_SOLVERS_FREE_PART_HPP

#include <cstdint>
#include <cstring>
#include <type_traits>

namespace gfmd {

// held is 0 (free) or 1 (held)
template <class T>
inline T free_part(T v, unsigned char held) {
    static_assert(std::is_floating_point<T>::value && (sizeof(T) == 4 || sizeof(T) == 8), "float or double");
    using Bits = typename std::conditional<sizeof(T) == 4, uint32_t, uint64_t>::type;
    Bits bits;
    std::memcpy(&bits, &v, sizeof bits);
    bits &= static_cast<Bits>(held) - Bits{1};  // held 1: every bit cleared (+0); 0: every bit kept
    std::memcpy(&v, &bits, sizeof v);
    return v;
}

}  // namespace gfmd

#endif
