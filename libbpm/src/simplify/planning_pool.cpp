#include "simplify/planning_pool.h"

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <stdexcept>

namespace bpm::detail {

int planning_threads(int requested, int64_t triangles) {
    if (requested > 0) return std::min(requested, 64);
    if (triangles < kSmallInputTriangles) return 1;
    const unsigned cores = std::thread::hardware_concurrency();
    if (cores < 2) return 1;
    double load = 0.0;
    if (getloadavg(&load, 1) == 1 && load >= double(cores)) return 1;
    return 2;
}

namespace {

void pause() {
#if defined(__x86_64__) || defined(__i386__)
    __builtin_ia32_pause();
#else
    std::this_thread::yield();
#endif
}

}  // namespace

PlanningPool::PlanningPool(int threads) {
    for (int i = 1; i < threads; ++i) workers_.emplace_back([this, i] { serve(i); });
}

PlanningPool::~PlanningPool() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stop_ = true;
    }
    wake_.notify_all();
    for (auto& w : workers_) w.join();
}

void PlanningPool::run(size_t tasks, WorkRef work) {
    if (workers_.empty() || tasks < 2) {
        for (size_t i = 0; i < tasks; ++i) work(0, i);
        return;
    }
    if (tasks > kIndexMask) throw std::length_error("planning round with too many tasks");
    work_ = work;
    failure_ = nullptr;
    done_.store(0);
    round_id_ = (round_id_ + 1) & kRoundMask;
    slot_.store((round_id_ << 40) | (uint64_t(tasks) << 20));
    round_.fetch_add(1);
    if (sleeping_.load() > 0) {
        std::lock_guard<std::mutex> lock(mutex_);
        wake_.notify_all();
    }
    take_tasks(0);
    while (done_.load() < tasks) pause();
    if (failure_) std::rethrow_exception(failure_);
}

void PlanningPool::take_tasks(int thread) {
    uint64_t v = slot_.load();
    while (true) {
        const size_t i = v & kIndexMask, tasks = (v >> 20) & kIndexMask;
        if (i >= tasks) return;
        if (!slot_.compare_exchange_weak(v, v + 1)) continue;  // v is reloaded
        try {
            work_(thread, i);
        } catch (...) {
            {
                std::lock_guard<std::mutex> lock(failure_mutex_);
                if (!failure_) failure_ = std::current_exception();
            }
            skip_rest();
        }
        done_.fetch_add(1);
        v = slot_.load();
    }
}

// After a failed task: the round's tasks not taken yet are taken at once and counted as
// done, unrun (the contract lets them be skipped). A cancelled first ranking (bpm::Cancelled
// from the progress report of thread 0) then ends without ranking the rest, and no later
// task of the round reports progress again.
void PlanningPool::skip_rest() {
    uint64_t v = slot_.load();
    while (true) {
        const size_t i = v & kIndexMask, tasks = (v >> 20) & kIndexMask;
        if (i >= tasks) return;
        if (slot_.compare_exchange_weak(v, v - i + tasks)) {  // next = tasks, same round
            done_.fetch_add(tasks - i);
            return;
        }
    }
}

void PlanningPool::serve(int thread) {
    uint64_t seen = 0;
    while (true) {
        const auto spin_until = std::chrono::steady_clock::now() + std::chrono::microseconds(200);
        bool spinning = true;
        for (int k = 0; round_.load() == seen; ++k) {
            if ((k & 255) == 255 && std::chrono::steady_clock::now() > spin_until) {
                spinning = false;
                break;
            }
            pause();
        }
        if (!spinning) {
            std::unique_lock<std::mutex> lock(mutex_);
            sleeping_.fetch_add(1);
            wake_.wait(lock, [&] { return stop_ || round_.load() != seen; });
            sleeping_.fetch_sub(1);
            if (stop_) return;
        }
        seen = round_.load();
        take_tasks(thread);
    }
}

}  // namespace bpm::detail
