#include "thread_pool.hpp"

#include <fftw3.h>
#include <omp.h>
#include <sched.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

namespace gfmd {

namespace {

// Polls before sleeping: each a sched_yield, so a waiting thread gives its core to whoever needs
// it.  5000 (a few ms on a quiet core) bridge the gaps between the parallel loops of a step; 200
// lost the quiet 1024^2 speed-up to wake-up latency (docs/decisions.md).
constexpr int kSpins = 5000;

thread_local ThreadPool *current_pool = nullptr;  // the pool of the transform being executed
thread_local bool in_job = false;                 // this thread is running a job of a pool

}  // namespace

ThreadPool::ThreadPool(int threads) {
    workers_.reserve(static_cast<std::size_t>(std::max(threads - 1, 0)));
    try {
        for (int t = 1; t < threads; ++t) workers_.emplace_back([this] { worker(); });
    } catch (...) {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            stop_ = true;
        }
        wake_.notify_all();
        for (auto &w : workers_) w.join();
        throw;
    }
}

ThreadPool::~ThreadPool() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stop_ = true;
    }
    wake_.notify_all();
    for (auto &w : workers_) w.join();
}

bool ThreadPool::inside_job() { return in_job; }

void ThreadPool::take_jobs(JobFn fn, void *ctx, int64_t njobs) {
    in_job = true;
    for (int64_t i = next_.fetch_add(1, std::memory_order_relaxed); i < njobs;
         i = next_.fetch_add(1, std::memory_order_relaxed)) {
        fn(ctx, i);
        finished_.fetch_add(1, std::memory_order_release);
    }
    in_job = false;
}

void ThreadPool::dispatch(int64_t njobs, JobFn fn, void *ctx) {
    {
        std::unique_lock<std::mutex> lock(mutex_);
        // A worker that woke late for the last task may still be leaving it: let it go first, so
        // that it never takes a job index of this one.
        idle_.wait(lock, [&] { return busy_.load(std::memory_order_relaxed) == 0; });
        fn_ = fn;
        ctx_ = ctx;
        njobs_ = njobs;
        next_.store(0, std::memory_order_relaxed);
        finished_.store(0, std::memory_order_relaxed);
        ++generation_;
        published_.store(generation_, std::memory_order_release);
    }
    wake_.notify_all();
    take_jobs(fn, ctx, njobs);
    // Done when every job has finished and no worker is still inside the task.
    auto done = [&] {
        return finished_.load(std::memory_order_acquire) == njobs && busy_.load(std::memory_order_acquire) == 0;
    };
    for (int s = 0; s < kSpins && !done(); ++s) std::this_thread::yield();
    if (!done()) {
        std::unique_lock<std::mutex> lock(mutex_);
        idle_.wait(lock, done);
    }
}

void ThreadPool::worker() {
    uint64_t seen = 0;
    for (;;) {
        for (int s = 0; s < kSpins && published_.load(std::memory_order_acquire) == seen; ++s)
            std::this_thread::yield();
        std::unique_lock<std::mutex> lock(mutex_);
        wake_.wait(lock, [&] { return stop_ || generation_ != seen; });
        if (stop_) return;
        seen = generation_;
        const JobFn fn = fn_;
        void *const ctx = ctx_;
        const int64_t njobs = njobs_;
        busy_.fetch_add(1, std::memory_order_relaxed);
        lock.unlock();
        take_jobs(fn, ctx, njobs);
        lock.lock();
        busy_.fetch_sub(1, std::memory_order_release);
        lock.unlock();
        idle_.notify_all();
    }
}

namespace {

// The CPUs of a cgroup CPU quota, rounded up; 0 if there is none (cgroup v2, then v1).
int cgroup_cpus() {
    auto read_two = [](const char *path, double &a, double &b, bool &unlimited) {
        std::FILE *f = std::fopen(path, "r");
        if (f == nullptr) return false;
        char buf[64] = "";
        const bool got = std::fgets(buf, sizeof buf, f) != nullptr;
        std::fclose(f);
        if (!got) return false;
        unlimited = std::strncmp(buf, "max", 3) == 0;
        if (!unlimited) a = std::strtod(buf, nullptr);
        const char *sp = std::strchr(buf, ' ');
        b = sp ? std::strtod(sp + 1, nullptr) : 0.0;
        return true;
    };
    double quota = 0.0, period = 0.0;
    bool unlimited = false;
    if (read_two("/sys/fs/cgroup/cpu.max", quota, period, unlimited))
        return (unlimited || !(quota > 0.0) || !(period > 0.0)) ? 0 : static_cast<int>(std::ceil(quota / period));
    double dummy = 0.0;
    if (read_two("/sys/fs/cgroup/cpu/cpu.cfs_quota_us", quota, dummy, unlimited) &&
        read_two("/sys/fs/cgroup/cpu/cpu.cfs_period_us", period, dummy, unlimited) && quota > 0.0 && period > 0.0)
        return static_cast<int>(std::ceil(quota / period));
    return 0;
}

}  // namespace

int default_threads() {
    if (const char *env = std::getenv("OMP_NUM_THREADS"); env != nullptr && *env != '\0')
        return std::max(omp_get_max_threads(), 1);
    int n = 0;
    cpu_set_t set;
    CPU_ZERO(&set);
    if (sched_getaffinity(0, sizeof set, &set) == 0) n = CPU_COUNT(&set);
    if (n <= 0) n = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    const int quota = cgroup_cpus();
    if (quota > 0) n = std::min(n, quota);
    return std::max(n, 1);
}

PoolScope::PoolScope(ThreadPool *pool) : previous_(current_pool) { current_pool = pool; }
PoolScope::~PoolScope() { current_pool = previous_; }

namespace {
void spawn_loop(void *(*work)(char *), char *jobdata, size_t elsize, int njobs, void *) {
    ThreadPool *pool = current_pool;
    if (pool != nullptr || in_job) {  // ours (nested in a job, run() keeps it on this thread)
        auto job = [&](int64_t i) { work(jobdata + elsize * static_cast<std::size_t>(i)); };
        if (pool != nullptr) {
            pool->run(njobs, job);
        } else {
            for (int i = 0; i < njobs; ++i) job(i);
        }
    } else {  // a plan that is not ours: what FFTW's OpenMP backend does
#pragma omp parallel for num_threads(njobs) schedule(static)
        for (int i = 0; i < njobs; ++i) work(jobdata + elsize * static_cast<std::size_t>(i));
    }
}
}  // namespace

void install_fftw_callback() { fftw_threads_set_callback(spawn_loop, nullptr); }

}  // namespace gfmd
