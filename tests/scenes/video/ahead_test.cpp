// Ahead<T>: the results in order, never more than `depth` ahead, the
// producer's exception at the result it would have made, and a stop that
// leaves nothing running.
#include "scenes/video/ahead.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <thread>

namespace scenes {
namespace {

TEST(Ahead, HandsOverEveryResultInOrderOnItsOwnThread) {
    const std::thread::id here = std::this_thread::get_id();
    std::atomic<bool> started{false};
    std::atomic<bool> elsewhere{true};
    Ahead<int> ahead(
        100, 2, [&] { started = true; },
        [&](int k) {
            elsewhere = elsewhere && std::this_thread::get_id() != here;
            return k * k;
        });
    for (int k = 0; k < 100; ++k) EXPECT_EQ(ahead.next(), k * k);
    EXPECT_THROW(ahead.next(), std::logic_error) << "a result past the count";
    EXPECT_TRUE(started);
    EXPECT_TRUE(elsewhere) << "make() ran on the caller's thread";
}

TEST(Ahead, MakesAtMostDepthResultsAheadOfThoseTaken) {
    std::atomic<int> made{0};
    Ahead<int> ahead(50, 3, nullptr, [&](int k) {
        ++made;
        return k;
    });
    for (int taken = 0; taken < 10; ++taken) {
        std::this_thread::sleep_for(std::chrono::milliseconds(20));  // time to run ahead, were it allowed
        // Made: those taken, `depth` waiting, and at most one in hand.
        EXPECT_LE(made.load(), taken + 3 + 1) << "after " << taken << " taken";
        EXPECT_EQ(ahead.next(), taken);
    }
}

TEST(Ahead, ThrowsTheProducersErrorWhereItsResultWouldBe) {
    Ahead<int> ahead(10, 2, nullptr, [](int k) {
        if (k == 4) throw std::runtime_error("step 4 failed");
        return k;
    });
    for (int k = 0; k < 4; ++k) EXPECT_EQ(ahead.next(), k);
    try {
        ahead.next();
        ADD_FAILURE() << "no error";
    } catch (const std::runtime_error& e) {
        EXPECT_STREQ(e.what(), "step 4 failed");
    }
}

TEST(Ahead, StopsWhenDestroyedBeforeAllIsTaken) {
    std::atomic<int> made{0};
    {
        Ahead<int> ahead(1'000'000, 2, nullptr, [&](int k) {
            ++made;
            return k;
        });
        EXPECT_EQ(ahead.next(), 0);
    }  // joins: the thread stopped waiting for room
    const int after = made.load();
    EXPECT_LE(after, 1 + 2 + 1);
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    EXPECT_EQ(made.load(), after) << "still making after the Ahead was destroyed";
}

}  // namespace
}  // namespace scenes
