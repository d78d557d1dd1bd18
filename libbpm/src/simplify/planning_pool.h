#pragma once
// Threads that share the work of the simplifier's rounds (planning, validation,
// re-ranking, export). Internal to libbpm.
//
// Contract:
// - run_round(n, work) runs work(thread, i) exactly once for every task i in [0, n) and
//   returns when all n have returned. `thread` is in [0, threads()); 0 is the caller,
//   which takes tasks too. Each thread starts its tasks in increasing order of i, and
//   tasks are handed out in increasing order (a task may wait for an earlier one of the
//   same round: VertexRemover::finish_part relies on that).
// - Which thread runs which task depends on timing; so a task must write only its own
//   outputs (or per-thread buffers indexed by `thread`), and then the results do not
//   depend on the number of threads.
// - If a task throws, run_round rethrows that exception (the first caught) on the caller
//   once no task of the round is running any more; the tasks no thread has taken when
//   one fails are skipped. The pool stays usable.
// - One round at a time, from one caller thread; rounds of at most 2^20 - 1 tasks
//   (std::length_error otherwise).
//
// Rounds are short (a few plans, tens of microseconds) and follow each other quickly,
// so a thread with nothing to do spins for a while before it sleeps. The caller waiting
// for a worker's last task spins 30 us (kSpin in planning_pool.cpp). A worker between
// rounds spins as long as its recent waits after rounds of the same kind say pays, at
// most 100 us (SpinBudget below): on a busy machine or through long gaps not at all (a
// fixed 200 us, then 30 us, spun through most gaps: 1.3-1.6x the CPU of one thread).

#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <mutex>
#include <thread>
#include <type_traits>
#include <vector>

namespace bpm::detail {

// Inputs with fewer triangles than this simplify on one thread when the thread count is
// automatic: a second thread saved them no wall time and cost 1.5-1.7x the CPU time
// (elephant 5.6k triangles, femur 7.8k; at 10k mech-holes-shark saved 11 % of the wall
// time for 1.5x the CPU, fandisk at 13k 28 % for 1.3x; --vertices 1000, loaded machine).
// The parts that two threads share well (the first ranking, the input check beside
// the set-up, the export) are too small there to pay for the second thread's spinning
// between the removals' short rounds.
constexpr int64_t kSmallInputTriangles = 10000;

// Threads for a simplification of an input of `triangles` triangles asked for
// `requested` (SimplifyOptions::threads): that, at most 64, or for 0 one for a small
// input (kSmallInputTriangles), else two unless the machine has one core or every core
// is busy (the 1-minute load average; the second thread spins between rounds, so bpm's
// own earlier runs count in the load too).
int planning_threads(int requested, int64_t triangles);

// How long a worker spins for the next round before it sleeps, learnt from its own recent
// waits (ski rental): spinning through a wait of w costs w of CPU time; sleeping costs
// kWakeCostMicros (the futex calls of the sleeper and of the thread that wakes it) plus
// the spin before it. The budget is the one of 0, 5, 20, 50, 100 us that would have cost
// least over the last few hundred waits: 0 when the waits are long (the other thread in
// a long plan, or a busy machine, where the waiting thread is often descheduled and a
// spin takes the core from the thread it waits for), 5-100 us when most are short (the
// gaps between the rounds of a step). One wait alone longer than kWakeCostMicros is
// cheaper slept through at once, but the budget is one for all waits: once most waits
// are short enough to spin through a budget b, spinning on through a gap shorter than
// b + kWakeCostMicros costs less than b spun plus a wake-up (after b = 20 us, the gaps
// under 40 us; the 20-50 us gaps of a step, the commits, average 29 us), while every wait
// longer than the new budget costs the difference more. choose() weighs both on the
// recorded waits; with budgets up to 20 us those gaps were left to sleeps. What a sleep
// costs besides is wall time on the critical path: the caller's notify (below) and the
// worker joining the next round late. Only timing: which thread runs a task never changes
// a result.
class SpinBudget {
public:
    static constexpr int kChoices = 5;
    static constexpr double kBudgetMicros[kChoices] = {0, 5, 20, 50, 100};
    // A sleep and wake-up of a thread. On the 2-core Firecracker VM of bench/RESULTS.md
    // (where a system call is dear) a two-thread probe measured the notify alone at 6-7 us
    // of the notifier's time (median; 15 us at the 90th percentile), on the caller's
    // critical path, and the sleeper awake 3-4 us after it (35 us at the 90th percentile);
    // the sleeper's own futex calls were not measured. 20 us counts some of that latency:
    // with 10 us and budgets up to 10 us the worker slept through every gap between rounds
    // longer than 10 us. Loop^1 208k -> 10k on an idle machine, two threads against one,
    // alt.py 7 rounds (2026-12-07, load ~1.3): wall 0.965x for 1.53x the CPU; with 20 us
    // (and budgets up to 20 us) 0.916x for 1.54x. Across runs of the same binaries two
    // threads' wall varied from 0.74x to 0.97x: compare within one run.
    // The same input with the worker never sleeping (a measurement build) had these waits
    // per run: 65k under 5 us (0.14 s in all), 46k of 5-20 us (0.53 s), 36k of 20-50 us
    // (1.06 s), 4k of 50-100 us (0.26 s), 214 longer (0.25 s); never sleeping cost 0.5 s
    // less system time than sleeping (~69k wake-ups: ~7 us of system time each) and 1.35 s
    // more user time. Budgets up to 100 us (the rule above picks 50-100 us on these waits),
    // alt.py 7 rounds, idle: two threads' wall 0.926x -> 0.880x one thread's, CPU 1.51x ->
    // 1.53x.
    static constexpr double kWakeCostMicros = 20;
    static constexpr int kWindow = 128;  // waits between choices; older waits count half

    // The current budget in microseconds (the longest until kWindow waits were seen).
    double micros() const { return kBudgetMicros[choice_]; }
    // One wait for a round: from the end of the worker's last task until the round was
    // published (whether spun or slept through; 0 if it came first).
    void record(double waited_micros);

private:
    void choose();
    double count_[kChoices] = {};  // waits between kBudgetMicros[i] and [i + 1] (the last: longer)
    double sum_[kChoices] = {};    // their total length, us
    int since_ = 0;
    int choice_ = kChoices - 1;
};

class PlanningPool {
public:
    // `threads` >= 1: the caller and threads - 1 workers.
    explicit PlanningPool(int threads);
    ~PlanningPool();
    PlanningPool(const PlanningPool&) = delete;
    PlanningPool& operator=(const PlanningPool&) = delete;

    int threads() const { return static_cast<int>(workers_.size()) + 1; }

    // `work(int thread, size_t task)`; see the contract above. `work` is used only
    // during the call. `kind` (0 .. kKinds - 1) names what comes after the round: the
    // workers learn a spin budget per kind (the simplifier's re-ranking round is followed
    // by a short pick, its plan round by the other thread's longer plan).
    static constexpr int kKinds = 4;
    template <class Work>
    void run_round(size_t tasks, Work&& work, int kind = 0) {
        using W = std::remove_reference_t<Work>;
        run(tasks,
            WorkRef{const_cast<void*>(static_cast<const void*>(&work)),
                    [](void* w, int thread, size_t i) { (*static_cast<W*>(w))(thread, i); }},
            kind);
    }

private:
    // The round's work, without copying or allocating (rounds are many and short).
    struct WorkRef {
        void* object = nullptr;
        void (*call)(void*, int, size_t) = nullptr;
        void operator()(int thread, size_t i) const { call(object, thread, i); }
    };
    void run(size_t tasks, WorkRef work, int kind);
    void take_tasks(int thread);
    void skip_rest();
    void wait_until_done(size_t tasks);
    void serve(int thread);

    std::vector<std::thread> workers_;
    // Written by the caller before it publishes a round in slot_; read by a worker only
    // after it took a task of that round (the compare-and-swap on slot_ orders them).
    WorkRef work_;
    std::atomic<uint64_t> round_{0};  // wakes the workers
    // When the caller published the last round (steady_clock ticks): a worker's wait for
    // it, for its SpinBudget, without the wake-up latency of a worker that slept.
    std::atomic<int64_t> published_{0};
    std::atomic<int> kind_{0};  // of the last round published (run_round)
    // The round's tasks: (round id << 40) | (number of tasks << 20) | next task. A task is
    // taken by a compare-and-swap of the whole word, so a thread that comes late from an
    // earlier round can never take (or count) a task of a later one. (A shared counter
    // reset per round let a late fetch_add run a task of the next round twice, once
    // with the previous round's task count.)
    static constexpr uint64_t kIndexMask = (uint64_t(1) << 20) - 1, kRoundMask = (uint64_t(1) << 24) - 1;
    std::atomic<uint64_t> slot_{0};
    uint64_t round_id_ = 0;
    std::atomic<size_t> done_{0};
    std::atomic<int> sleeping_{0};
    std::mutex mutex_;  // guards stop_ and the sleeping side of round_
    std::condition_variable wake_;
    bool stop_ = false;
    // The caller sleeps on done_wake_ when a worker's task outlasts its spin.
    std::atomic<bool> caller_sleeping_{false};
    std::mutex done_mutex_;
    std::condition_variable done_wake_;
    std::mutex failure_mutex_;
    std::exception_ptr failure_;
};

}  // namespace bpm::detail
