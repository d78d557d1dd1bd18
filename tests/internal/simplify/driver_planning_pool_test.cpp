// The simplifier's thread pool (simplify/planning_pool.h), tested directly: every task of
// every round runs exactly once, whatever the thread count (a late worker of an earlier
// round once ran a task of the next round twice), the caller is thread 0, and an
// exception in a task reaches the caller without breaking the pool.
#include <atomic>
#include <chrono>
#include <cstdint>
#include <set>
#include <stdexcept>
#include <thread>
#include <vector>

#include <catch2/catch.hpp>

#include "simplify/planning_pool.h"

using bpm::detail::PlanningPool;

namespace {

// Many short rounds of varying size, as the simplifier makes them; per task the number
// of times it ran and a value that depends only on (round, task).
void run_many_rounds(PlanningPool& pool, std::vector<uint64_t>& sums) {
    sums.clear();
    for (int round = 0; round < 1000; ++round) {
        const size_t tasks = size_t(1 + (round * 7) % 13);
        std::vector<std::atomic<int>> runs(tasks);
        std::vector<uint64_t> value(tasks, 0);
        std::atomic<int> bad_thread{0};
        // Of every kind, as the simplifier's steps (plan, validation, re-ranking) and an
        // out-of-range kind (clamped): the kind only sets the workers' spin.
        pool.run_round(tasks, [&](int thread, size_t i) {
            if (thread < 0 || thread >= pool.threads()) bad_thread.fetch_add(1);
            runs[i].fetch_add(1);
            value[i] = uint64_t(round) * 1000003u + i * i;
        }, round % (PlanningPool::kKinds + 1));
        REQUIRE(bad_thread.load() == 0);
        uint64_t sum = 0;
        for (size_t i = 0; i < tasks; ++i) {
            REQUIRE(runs[i].load() == 1);
            sum = sum * 31 + value[i];
        }
        sums.push_back(sum);
    }
}

}  // namespace

TEST_CASE("planning pool: every task of every round runs once, the same for 1, 2 and 3 threads",
          "[internal][simplify]") {
    std::vector<uint64_t> one, two, three;
    {
        PlanningPool pool(1);
        REQUIRE(pool.threads() == 1);
        run_many_rounds(pool, one);
    }
    {
        PlanningPool pool(2);
        REQUIRE(pool.threads() == 2);
        run_many_rounds(pool, two);
    }
    {
        PlanningPool pool(3);
        run_many_rounds(pool, three);
    }
    CHECK(one == two);
    CHECK(one == three);
}

TEST_CASE("planning pool: a round of one task and a round of none run on the caller", "[internal][simplify]") {
    PlanningPool pool(2);
    std::set<int> threads;
    pool.run_round(1, [&](int thread, size_t) { threads.insert(thread); });
    CHECK(threads == std::set<int>{0});
    bool ran = false;
    pool.run_round(0, [&](int, size_t) { ran = true; });
    CHECK(!ran);
}

TEST_CASE("planning pool: a task's exception reaches the caller and the pool keeps working",
          "[internal][simplify]") {
    for (int threads : {1, 2}) {
        PlanningPool pool(threads);
        auto throwing = [](int, size_t i) {
            if (i == 5) throw std::runtime_error("task 5 failed");
        };
        CHECK_THROWS_WITH(pool.run_round(10, throwing), "task 5 failed");
        std::vector<std::atomic<int>> runs(10);
        pool.run_round(10, [&](int, size_t i) { runs[i].fetch_add(1); });
        for (auto& r : runs) CHECK(r.load() == 1);
    }
}

TEST_CASE("planning pool: after a task fails, the tasks no thread has taken are skipped",
          "[internal][simplify]") {
    // Task 0 fails at once; the others take a while each. Without skipping, all 1999 ran
    // (a cancelled first ranking went on ranking, and reporting progress, to its end).
    // The others sleep rather than spin, so that the failing thread gets a core even on a
    // busy machine (spinning tasks with a bound of 100 failed under a parallel build: the
    // failing thread was descheduled between its throw and the skip); half is the bound.
    for (int threads : {1, 2, 3}) {
        CAPTURE(threads);
        PlanningPool pool(threads);
        std::atomic<int> ran{0};
        auto work = [&](int, size_t i) {
            if (i == 0) throw std::runtime_error("task 0 failed");
            ++ran;
            std::this_thread::sleep_for(std::chrono::microseconds(100));
        };
        CHECK_THROWS_WITH(pool.run_round(2000, work), "task 0 failed");
        CHECK(ran.load() < 1000);
        std::atomic<int> after{0};
        pool.run_round(50, [&](int, size_t) { ++after; });  // still usable, every task runs
        CHECK(after.load() == 50);
    }
}

TEST_CASE("planning pool: a task may wait for an earlier task of its round", "[internal][simplify]") {
    // VertexRemover::finish_part: part 0 prepares, the later parts wait for it. Tasks are
    // handed out in order, so with any number of threads the waiting task cannot hold up
    // the one it waits for.
    PlanningPool pool(2);
    for (int round = 0; round < 500; ++round) {
        std::atomic<bool> prepared{false};
        std::atomic<int> saw_prepared{0};
        pool.run_round(2, [&](int, size_t i) {
            if (i == 0) {
                prepared.store(true);
            } else {
                while (!prepared.load()) {
                }
                saw_prepared.fetch_add(1);
            }
        });
        REQUIRE(saw_prepared.load() == 1);
    }
}

TEST_CASE("planning pool: too many tasks for one round are refused", "[internal][simplify]") {
    PlanningPool pool(2);
    CHECK_THROWS_AS(pool.run_round(size_t(1) << 20, [](int, size_t) {}), std::length_error);
}

TEST_CASE("planning threads: automatic is one thread for a small input, else what was asked",
          "[internal][simplify]") {
    using bpm::detail::kSmallInputTriangles;
    using bpm::detail::planning_threads;
    // elephant (5558 triangles): a second thread saved no wall time and cost 1.7x the CPU.
    CHECK(planning_threads(0, 5558) == 1);
    CHECK(planning_threads(0, kSmallInputTriangles - 1) == 1);
    const int large = planning_threads(0, kSmallInputTriangles);
    CHECK((large == 1 || large == 2));  // 1 on a one-core or busy machine
    CHECK(planning_threads(2, 5558) == 2);  // asked for: as asked
    CHECK(planning_threads(3, 100) == 3);
    CHECK(planning_threads(100, 1000000) == 64);
}

TEST_CASE("planning pool: threads that went to sleep (a worker between rounds, the caller on a slow task) wake for "
          "every round",
          "[internal][simplify]") {
    // Pauses between rounds and tasks slower than the pool's spins: the workers sleep
    // before the next round, and the caller sleeps while a worker finishes the slow
    // task. A lost wake-up would hang here; a task run twice or not at all fails.
    for (int threads : {2, 3}) {
        CAPTURE(threads);
        PlanningPool pool(threads);
        for (int round = 0; round < 40; ++round) {
            if (round % 2 == 0) std::this_thread::sleep_for(std::chrono::milliseconds(2));
            const size_t tasks = size_t(2 + round % 3);
            std::vector<std::atomic<int>> runs(tasks);
            pool.run_round(tasks, [&](int, size_t i) {
                if (i == 1) std::this_thread::sleep_for(std::chrono::milliseconds(1));
                runs[i].fetch_add(1);
            });
            for (size_t i = 0; i < tasks; ++i) REQUIRE(runs[i].load() == 1);
        }
    }
}

TEST_CASE("spin budget: a worker spins through short waits and sleeps at once through long ones",
          "[internal][simplify]") {
    // A fixed 30 us spin burnt a core through every long wait (the other thread's slow plan,
    // a busy machine) and gained nothing there: 1.3x the CPU of one thread.
    using bpm::detail::SpinBudget;
    auto after = [](std::initializer_list<std::pair<double, int>> waits) {
        SpinBudget b;
        for (int window = 0; window < 4; ++window)
            for (const auto& [micros, share] : waits)
                for (int i = 0; i < share * SpinBudget::kWindow / 100; ++i) b.record(micros);
        return b.micros();
    };
    CHECK(SpinBudget().micros() == 100);           // until it has seen waits
    CHECK(after({{200.0, 100}}) == 0);             // long waits only: sleep at once
    CHECK(after({{1.0, 100}}) == 5);               // the shortest budget that covers them
    CHECK(after({{3.0, 100}}) == 5);
    CHECK(after({{8.0, 100}}) == 20);
    CHECK(after({{15.0, 100}}) == 20);             // 15 us spun is cheaper than a wake-up (20)
    CHECK(after({{25.0, 100}}) == 0);              // 25 us spun is dearer than a wake-up
    CHECK(after({{3.0, 70}, {200.0, 30}}) == 5);   // 0.7 * 3 + 0.3 * (5 + 20) < 20
    CHECK(after({{3.0, 20}, {200.0, 80}}) == 0);   // 0.2 * 3 + 0.8 * 25 > 20
    // Short waits and 30 us ones: 50 us (0.6 * 10 + 0.4 * 30 = 18) beats sleeping at once
    // (20) and 20 us (0.6 * 10 + 0.4 * (20 + 20) = 22), though 30 us alone is dearer
    // spun than slept. (100 us costs the same as 50 here: a tie keeps the shorter.)
    CHECK(after({{10.0, 60}, {30.0, 40}}) == 50);
    // The waits of Loop^1 armadillo on two threads (planning_pool.h): 100 us.
    CHECK(after({{2.0, 43}, {12.0, 30}, {29.0, 24}, {62.0, 3}}) == 100);
}

TEST_CASE("spin budget: it follows a change of the waits", "[internal][simplify]") {
    // A busy machine (long waits) that becomes idle (short ones): the budget comes back.
    using bpm::detail::SpinBudget;
    SpinBudget b;
    for (int i = 0; i < 4 * SpinBudget::kWindow; ++i) b.record(500.0);
    REQUIRE(b.micros() == 0);
    for (int i = 0; i < 4 * SpinBudget::kWindow; ++i) b.record(4.0);
    CHECK(b.micros() == 5);
}
