// FFTW's process-wide state as the library uses it: one mutex around planning, plan destruction,
// thread setup and wisdom (none of them is thread-safe), and wisdom set aside for ESTIMATE plans.
#ifndef GFMD_SRC_FFTW_PLANNER_HPP
#define GFMD_SRC_FFTW_PLANNER_HPP

#include <fftw3.h>

#include <cstdint>
#include <mutex>
#include <new>

namespace gfmd {

std::mutex &planner_mutex();

// Below this many points one thread transforms faster than two (measured on 2 cores).
constexpr int64_t kMinPointsForThreads = 128 * 128;

// FFTW's threads, initialized once before any plan or wisdom (wisdom exported with threads only
// imports into a process whose threads are initialized).  Call with the planner mutex held.
bool threads_ready();

// Wisdom set aside while an ESTIMATE plan is made, and given back after.  FFTW plans from wisdom of
// an equal or more rigorous planner when it has some, so an ESTIMATE plan made after a MEASURE plan
// of the same size would be the measured one, chosen by timings: other bits in another process.
// Without the wisdom it is FFTW's deterministic estimate, the same in every process.
class WisdomAside {
public:
    explicit WisdomAside(bool active) : saved_(active ? fftw_export_wisdom_to_string() : nullptr) {
        if (active && saved_ == nullptr) throw std::bad_alloc();
        if (active) fftw_forget_wisdom();
    }
    WisdomAside(const WisdomAside &) = delete;
    WisdomAside &operator=(const WisdomAside &) = delete;
    ~WisdomAside() {
        if (saved_ == nullptr) return;
        fftw_forget_wisdom();  // the estimate's own entries: later ESTIMATE plans make them afresh
        fftw_import_wisdom_from_string(saved_);
        fftw_free(saved_);
    }

private:
    char *saved_;
};

}  // namespace gfmd

#endif
