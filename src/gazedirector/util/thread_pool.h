#pragma once

#include <condition_variable>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace gazedirector {

// A fixed set of worker threads for data-parallel loops. ParallelFor runs
// body(index, worker) for index in [0, count), each worker taking the next
// index, and returns when all are done; `worker` (0..size()-1) lets the body
// use per-thread scratch (a renderer, buffers). The calling thread works too.
// An exception thrown by a body stops the loop and is rethrown to the caller.
class ThreadPool {
 public:
  explicit ThreadPool(int threads = DefaultThreads());
  ~ThreadPool();
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;

  int size() const { return static_cast<int>(workers_.size()) + 1; }
  void ParallelFor(int count, const std::function<void(int index, int worker)>& body);

  // The hardware's threads, or GAZEDIRECTOR_THREADS when set.
  static int DefaultThreads();

 private:
  void Work(int worker);
  void RunShare(int worker);

  std::vector<std::thread> workers_;
  std::mutex mutex_;
  std::condition_variable start_;
  std::condition_variable done_;
  const std::function<void(int, int)>* body_ = nullptr;
  int count_ = 0;
  int next_ = 0;
  int busy_ = 0;
  long generation_ = 0;
  bool stopping_ = false;
  std::exception_ptr error_;
};

}  // namespace gazedirector
