// Worker: one persistent thread that runs one fixed job on request (no Python types).
//
// The whole-body controller uses it to compute the dynamics terms of the measured state while the
// caller's thread prepares the reference (WbcSolver::prepare). A job is started with start() and
// waited for with wait(); start() requires the previous job to have been waited for.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <thread>

#ifdef _WIN32
#include <process.h>
#define LIPMPCC_GETPID ::_getpid
#else
#include <unistd.h>
#define LIPMPCC_GETPID ::getpid
#endif

namespace lipmpcc::wbc {

class Worker {
 public:
  /// `job` runs on the worker thread, once per start(). It must not throw.
  explicit Worker(std::function<void()> job) : job_(std::move(job)), thread_([this] { loop(); }) {}
  Worker(const Worker&) = delete;
  Worker& operator=(const Worker&) = delete;
  ~Worker() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    wake_.notify_one();
    thread_.join();
  }

  /// False in a child process forked after the worker started: there the thread does not exist (the
  /// owner must drop this object without destroying it, and make a new one).
  bool inThisProcess() const { return pid_ == LIPMPCC_GETPID(); }

  /// Runs the job on the worker thread; returns at once.
  void start() {
    done_.store(false, std::memory_order_relaxed);
    {
      std::lock_guard<std::mutex> lock(mutex_);
      requested_ = true;
    }
    wake_.notify_one();
  }

  /// Returns once the job started last has finished (at once when none is running). Spins for a
  /// short while before sleeping: the job is usually done or about to be.
  void wait() const {
    const auto t0 = std::chrono::steady_clock::now();
    while (!done_.load(std::memory_order_acquire)) {
      if (std::chrono::steady_clock::now() - t0 > std::chrono::microseconds(200)) {
        std::unique_lock<std::mutex> lock(mutex_);
        finished_.wait(lock, [this] { return done_.load(std::memory_order_acquire); });
        return;
      }
      std::this_thread::yield();
    }
  }

 private:
  void loop() {
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
      wake_.wait(lock, [this] { return requested_ || stop_; });
      if (stop_) return;
      requested_ = false;
      lock.unlock();
      job_();
      lock.lock();
      done_.store(true, std::memory_order_release);
      finished_.notify_all();
    }
  }

  std::function<void()> job_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  mutable std::condition_variable finished_;
  bool requested_ = false;
  bool stop_ = false;
  std::atomic<bool> done_{true};
  const decltype(LIPMPCC_GETPID()) pid_ = LIPMPCC_GETPID();
  std::thread thread_;  // last: started once the members above exist
};

}  // namespace lipmpcc::wbc
