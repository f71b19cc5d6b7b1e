// Work done a few items ahead on a thread of its own: Ahead<T> calls
// make(k) for k = 0, 1, ..., count - 1 in order on its thread, at most
// `depth` results ahead of the ones taken, and next() hands them over in
// the same order. video steps the scenes and builds frame k + 1's draw lists
// while frame k is drawn and read back (physics and rendering overlap; each
// stays in its order, so the frames are the same bytes). An exception from
// make() is thrown again by the next() that would have taken its result;
// destroying an Ahead stops the thread after the item in hand.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <exception>
#include <functional>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>

namespace scenes {

template <class T>
class Ahead {
public:
    // `start` runs first on the thread (thread-local set-up), then make(k).
    Ahead(int count, std::size_t depth, std::function<void()> start, std::function<T(int)> make)
        : count_(count),
          depth_(depth),
          thread_([this, count, start = std::move(start), make = std::move(make)] { produce(count, start, make); }) {}
    ~Ahead() {
        {
            const std::lock_guard lock(mutex_);
            stop_ = true;
        }
        changed_.notify_all();
        thread_.join();
    }
    Ahead(const Ahead&) = delete;
    Ahead& operator=(const Ahead&) = delete;

    // The next result, in order; waits for it. Throws what make() threw, and
    // std::logic_error past the count (no result would ever come).
    T next() {
        if (taken_ >= count_) throw std::logic_error("Ahead: all " + std::to_string(count_) + " results taken");
        ++taken_;
        std::unique_lock lock(mutex_);
        changed_.wait(lock, [&] { return !ready_.empty() || error_ != nullptr; });
        if (ready_.empty()) std::rethrow_exception(error_);
        T item = std::move(ready_.front());
        ready_.pop_front();
        lock.unlock();
        changed_.notify_all();
        return item;
    }

private:
    void produce(int count, const std::function<void()>& start, const std::function<T(int)>& make) {
        try {
            if (start) start();
            for (int k = 0; k < count; ++k) {
                {
                    std::unique_lock lock(mutex_);
                    changed_.wait(lock, [&] { return stop_ || ready_.size() < depth_; });
                    if (stop_) return;
                }
                T item = make(k);
                {
                    const std::lock_guard lock(mutex_);
                    ready_.push_back(std::move(item));
                }
                changed_.notify_all();
            }
        } catch (...) {
            {
                const std::lock_guard lock(mutex_);
                error_ = std::current_exception();
            }
            changed_.notify_all();
        }
    }

    const int count_;
    int taken_ = 0;  // by next(), on the caller's thread
    const std::size_t depth_;
    std::mutex mutex_;
    std::condition_variable changed_;
    std::deque<T> ready_;
    std::exception_ptr error_;
    bool stop_ = false;
    std::thread thread_;  // last: it starts once the members above exist
};

}  // namespace scenes
