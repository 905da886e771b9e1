#pragma once
// Changes requested from ROS callbacks (reconfigure, services) run on the simulation thread
// between two steps, never inside one. Callbacks post a task and, when they must answer
// with a result, wait for its future.

#include <chrono>
#include <condition_variable>
#include <deque>
#include <functional>
#include <future>
#include <memory>
#include <mutex>

namespace pbf_ros {

class SimulationTasks {
 public:
  // Queues `task`; the future is ready once it ran on the simulation thread.
  template <typename Result>
  std::future<Result> post(std::function<Result()> task) {
    auto promise = std::make_shared<std::promise<Result>>();
    std::future<Result> future = promise->get_future();
    enqueue([promise, task]() {
      try {
        promise->set_value(task());
      } catch (...) {
        promise->set_exception(std::current_exception());
      }
    });
    return future;
  }

  // Queues a task nobody waits for.
  void enqueue(std::function<void()> task);

  // Simulation thread: runs every queued task in order. Returns how many ran.
  std::size_t runAll();

  // Simulation thread: sleeps until `deadline` or until a task is queued or wake() called.
  void waitUntil(std::chrono::steady_clock::time_point deadline);
  void wake();

 private:
  std::mutex mutex_;
  std::condition_variable wakeup_;
  std::deque<std::function<void()>> queue_;
  bool woken_ = false;
};

}  // namespace pbf_ros
