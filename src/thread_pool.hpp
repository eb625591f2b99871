// The library's own threads: a small pool per handle that runs the element-wise passes, the
// Fourier-space sums and (through FFTW's spawn-loop callback) FFTW's threaded loops.  Jobs are
// handed out one at a time, so a thread whose core is shared with another process simply takes
// fewer of them; waiting threads spin briefly, yielding the core, then sleep.  OpenMP's default
// barriers instead spin for long and split work evenly, which made two threads 2.5-3x slower than
// one as soon as one core was busy (docs/decisions.md).
#ifndef GFMD_SRC_THREAD_POOL_HPP
#define GFMD_SRC_THREAD_POOL_HPP

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <thread>
#include <type_traits>
#include <vector>

namespace gfmd {

class ThreadPool {
public:
    explicit ThreadPool(int threads);  // threads >= 1: threads - 1 workers beside the caller
    ThreadPool(const ThreadPool &) = delete;
    ThreadPool &operator=(const ThreadPool &) = delete;
    ~ThreadPool();

    int size() const { return static_cast<int>(workers_.size()) + 1; }

    // job(i) for every i in [0, njobs), on the pool's threads and the caller's; returns when all
    // are done.  Which thread runs which job varies; what a job computes must not depend on it.
    template <class Job>
    void run(int64_t njobs, Job &&job) {
        if (workers_.empty() || njobs <= 1 || inside_job()) {  // nested in a job: this thread alone
            for (int64_t i = 0; i < njobs; ++i) job(i);
            return;
        }
        using Callable = std::remove_reference_t<Job>;
        dispatch(njobs, [](void *ctx, int64_t i) { (*static_cast<Callable *>(ctx))(i); },
                 const_cast<void *>(static_cast<const void *>(&job)));
    }

    // True while this thread runs a job of some pool (nested parallel loops run serially: a
    // nested dispatch would wait for the very task it is part of).
    static bool inside_job();

private:
    using JobFn = void (*)(void *, int64_t);
    void dispatch(int64_t njobs, JobFn fn, void *ctx);
    void take_jobs(JobFn fn, void *ctx, int64_t njobs);
    void worker();

    std::vector<std::thread> workers_;
    std::mutex mutex_;
    std::condition_variable wake_, idle_;
    // The current task (written under mutex_ while no worker is busy).
    JobFn fn_ = nullptr;
    void *ctx_ = nullptr;
    int64_t njobs_ = 0;
    uint64_t generation_ = 0;              // under mutex_
    std::atomic<uint64_t> published_{0};   // generation_, readable without the lock for spinning
    std::atomic<int64_t> next_{0}, finished_{0};
    std::atomic<int> busy_{0};             // workers inside a task (changed under mutex_)
    bool stop_ = false;
};

// The default thread count: OMP_NUM_THREADS if the user set it, otherwise the CPUs this process
// may run on (its affinity mask), bounded by a cgroup CPU quota (containers, batch systems).
int default_threads();

// FFTW's threaded loops run on the pool of the transform this thread is executing (set by
// PoolScope); other threaded FFTW plans of the process keep FFTW's OpenMP behaviour.
void install_fftw_callback();
class PoolScope {
public:
    explicit PoolScope(ThreadPool *pool);
    ~PoolScope();
    PoolScope(const PoolScope &) = delete;
    PoolScope &operator=(const PoolScope &) = delete;

private:
    ThreadPool *previous_;
};

}  // namespace gfmd

#endif
