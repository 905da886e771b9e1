#include "pbf_ros/ros/SimulationTasks.h"

namespace pbf_ros {

void SimulationTasks::enqueue(std::function<void()> task) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    queue_.push_back(std::move(task));
  }
  wakeup_.notify_all();
}

std::size_t SimulationTasks::runAll() {
  std::deque<std::function<void()>> batch;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    batch.swap(queue_);
  }
  for (auto& task : batch) task();  // outside the lock: tasks may take a while
  return batch.size();
}

void SimulationTasks::waitUntil(std::chrono::steady_clock::time_point deadline) {
  std::unique_lock<std::mutex> lock(mutex_);
  wakeup_.wait_until(lock, deadline, [this] { return !queue_.empty() || woken_; });
  woken_ = false;
}

void SimulationTasks::wake() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    woken_ = true;
  }
  wakeup_.notify_all();
}

}  // namespace pbf_ros
