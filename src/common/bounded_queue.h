#pragma once
// A bounded multi-producer/multi-consumer queue for hand-offs between pipeline threads.
// Push blocks while the queue is full (back-pressure), Pop blocks while it is empty; Close()
// wakes everyone: after it, Push fails and Pop drains what is left, then returns nullopt.
// No polling: waiting is done on condition variables only.

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <mutex>
#include <optional>

namespace esdslam {

// What PushDropOldest did with the item.
enum class DropOldestPush { kQueued, kQueuedDroppedOldest, kClosed };

template <typename T>
class BoundedQueue {
 public:
  explicit BoundedQueue(std::size_t capacity) : capacity_(capacity == 0 ? 1 : capacity) {}

  // Blocks while full. Returns false if the queue was closed.
  bool Push(T item) {
    std::unique_lock<std::mutex> lock(mutex_);
    not_full_.wait(lock, [&] { return closed_ || items_.size() < capacity_; });
    if (closed_) return false;
    items_.push_back(std::move(item));
    not_empty_.notify_one();
    return true;
  }

  // Never blocks: if full, drops the oldest item (for "newest wins" hand-offs).
  DropOldestPush PushDropOldest(T item) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (closed_) return DropOldestPush::kClosed;
    const bool full = items_.size() >= capacity_;
    if (full) items_.pop_front();
    items_.push_back(std::move(item));
    not_empty_.notify_one();
    return full ? DropOldestPush::kQueuedDroppedOldest : DropOldestPush::kQueued;
  }

  // Blocks while empty and open. Returns nullopt once closed and drained.
  std::optional<T> Pop() {
    std::unique_lock<std::mutex> lock(mutex_);
    not_empty_.wait(lock, [&] { return closed_ || !items_.empty(); });
    if (items_.empty()) return std::nullopt;
    T item = std::move(items_.front());
    items_.pop_front();
    not_full_.notify_one();
    return item;
  }

  std::optional<T> TryPop() {
    std::lock_guard<std::mutex> lock(mutex_);
    if (items_.empty()) return std::nullopt;
    T item = std::move(items_.front());
    items_.pop_front();
    not_full_.notify_one();
    return item;
  }

  void Close() {
    std::lock_guard<std::mutex> lock(mutex_);
    closed_ = true;
    not_empty_.notify_all();
    not_full_.notify_all();
  }

  std::size_t Size() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return items_.size();
  }
  bool Closed() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return closed_;
  }

 private:
  const std::size_t capacity_;
  mutable std::mutex mutex_;
  std::condition_variable not_empty_;
  std::condition_variable not_full_;
  std::deque<T> items_;
  bool closed_ = false;
};

}  // namespace esdslam
