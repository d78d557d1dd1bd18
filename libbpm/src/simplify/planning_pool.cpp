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

// How long the caller spins while a worker finishes the round's last task, before it
// sleeps. (The workers' spin between rounds is learnt: SpinBudget.) Loop^1 armadillo
// (208k triangles) -> 10k vertices, R = 2, two threads, CPU seconds, median of 3
// alternated runs on a loaded machine (load 9-14; one thread: 8.64 s): workers spinning
// 200 us 13.8 s; 30 us 11.3 s; 30 us and the caller sleeping too 11.0 s; 10 us both
// 10.2 s. The caller seldom waits (the worker takes fewer tasks): 30 us.
constexpr std::chrono::microseconds kSpin(30);

void pause() {
#if defined(__x86_64__) || defined(__i386__)
    __builtin_ia32_pause();
#else
    std::this_thread::yield();
#endif
}

}  // namespace

constexpr double SpinBudget::kBudgetMicros[];

void SpinBudget::record(double waited_micros) {
    int i = kChoices - 1;
    while (i > 0 && waited_micros < kBudgetMicros[i]) --i;
    count_[i] += 1;
    sum_[i] += waited_micros;
    if (++since_ == kWindow) choose();
}

// The budget that would have cost least over the recorded waits: the waits it covers
// spun through, each longer one its budget plus a sleep. Then the old waits count half.
void SpinBudget::choose() {
    double best = 0;
    for (int b = 0; b < kChoices; ++b) {
        double cost = 0;
        for (int i = 0; i < kChoices; ++i)
            cost += i < b ? sum_[i] : count_[i] * (kBudgetMicros[b] + kWakeCostMicros);
        if (b == 0 || cost < best) {
            best = cost;
            choice_ = b;
        }
    }
    for (int i = 0; i < kChoices; ++i) {
        count_[i] *= 0.5;
        sum_[i] *= 0.5;
    }
    since_ = 0;
}

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

void PlanningPool::run(size_t tasks, WorkRef work, int kind) {
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
    published_.store(std::chrono::steady_clock::now().time_since_epoch().count(), std::memory_order_relaxed);
    kind_.store(std::clamp(kind, 0, kKinds - 1), std::memory_order_relaxed);
    round_.fetch_add(1);
    if (sleeping_.load() > 0) {
        // A worker reads round_ under the lock before it waits: taking the lock after the
        // change loses no wake-up. Notifying under the lock made the woken worker block on
        // the lock the caller still held (a futex call more on each side).
        { std::lock_guard<std::mutex> lock(mutex_); }
        wake_.notify_all();
    }
    take_tasks(0);
    wait_until_done(tasks);
    if (failure_) std::rethrow_exception(failure_);
}

// The caller, out of tasks: the workers finish theirs. A worker that counts a task done
// while the caller sleeps wakes it (take_tasks); the caller sets caller_sleeping_ before it
// reads done_ under the lock, so either it sees the count or the worker sees the flag.
void PlanningPool::wait_until_done(size_t tasks) {
    const auto spin_until = std::chrono::steady_clock::now() + kSpin;
    for (int k = 0; done_.load() < tasks; ++k) {
        if ((k & 15) == 15 && std::chrono::steady_clock::now() > spin_until) {
            std::unique_lock<std::mutex> lock(done_mutex_);
            caller_sleeping_.store(true);
            done_wake_.wait(lock, [&] { return done_.load() >= tasks; });
            caller_sleeping_.store(false);
            return;
        }
        pause();
    }
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
        if (thread != 0 && caller_sleeping_.load()) {
            { std::lock_guard<std::mutex> lock(done_mutex_); }  // as in run(): no lost wake-up
            done_wake_.notify_one();
        }
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

// A worker: spins for the next round as long as the budget of the kind of round it last
// worked in says, else sleeps until it comes; each wait is recorded for that budget.
void PlanningPool::serve(int thread) {
    uint64_t seen = 0;
    SpinBudget budgets[kKinds];
    int kind = 0;
    bool first = true;
    while (true) {
        SpinBudget& budget = budgets[kind];
        const auto idle_since = std::chrono::steady_clock::now();
        const auto spin_until = idle_since + std::chrono::duration<double, std::micro>(budget.micros());
        bool spinning = budget.micros() > 0;
        for (int k = 0; spinning && round_.load() == seen; ++k) {
            if ((k & 15) == 15 && std::chrono::steady_clock::now() > spin_until) {
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
        // The wait before the first round (the set-up) says nothing about the rounds.
        if (!first) {
            const std::chrono::steady_clock::duration published(published_.load(std::memory_order_relaxed));
            const auto waited = std::chrono::duration<double, std::micro>(published - idle_since.time_since_epoch());
            budget.record(std::max(0.0, waited.count()));
        }
        first = false;
        seen = round_.load();
        kind = kind_.load(std::memory_order_relaxed);  // a later round's at worst: only timing
        take_tasks(thread);
    }
}

}  // namespace bpm::detail
