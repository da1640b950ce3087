// A fixed set of worker threads for data-parallel loops (particles, TSBI's
// candidate areas, the SSO of a new keyframe's pairs, keyframe matches).
// Work is split by index; results must depend only on the index (each
// particle carries its own random stream), so the output is identical
// whatever the number of threads or their timing.
#pragma once

#include <condition_variable>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace hmt {

class WorkerPool {
 public:
  // threads <= 1 runs everything on the calling thread.
  explicit WorkerPool(int threads);
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  // Calls fn(i) for i in [0, n), returns when all are done. Exceptions
  // thrown by fn are rethrown here (the first one). Callable from several
  // threads (they take turns); fn must not call parallel_for on this pool.
  void parallel_for(size_t n, const std::function<void(size_t)>& fn);
  int threads() const { return static_cast<int>(workers_.size()) + 1; }
  // The thread count for a requested one: itself if > 0, else one per core.
  static int threads_for(int requested);

 private:
  void worker_loop();
  void run_chunk(std::unique_lock<std::mutex>& lock);

  std::vector<std::thread> workers_;
  std::mutex call_mutex_;           // held by the one parallel_for running
  std::mutex mutex_;                // guards every member below
  std::condition_variable wake_;    // new job or shutdown
  std::condition_variable done_;    // a worker finished its part
  const std::function<void(size_t)>* job_ = nullptr;
  size_t n_ = 0, next_ = 0;
  int busy_ = 0;
  unsigned generation_ = 0;
  bool stop_ = false;
  std::exception_ptr error_;
};

}  // namespace hmt
