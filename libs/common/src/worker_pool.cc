#include "hmt/common/worker_pool.h"

namespace hmt {

int WorkerPool::threads_for(int requested) {
  if (requested > 0) return requested;
  const unsigned hc = std::thread::hardware_concurrency();
  return hc ? static_cast<int>(hc) : 1;
}

WorkerPool::WorkerPool(int threads) {
  for (int i = 1; i < threads; ++i) workers_.emplace_back([this] { worker_loop(); });
}

WorkerPool::~WorkerPool() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  for (auto& t : workers_) t.join();
}

void WorkerPool::run_chunk(std::unique_lock<std::mutex>& lock) {
  // Indices are taken one at a time: particles differ a lot in cost, so a
  // static split would leave a thread idle.
  while (next_ < n_) {
    const size_t i = next_++;
    const auto* job = job_;
    lock.unlock();
    std::exception_ptr err;
    try {
      (*job)(i);
    } catch (...) {
      err = std::current_exception();
    }
    lock.lock();
    if (err) {
      if (!error_) error_ = err;
      next_ = n_;  // stop handing out work
    }
  }
}

void WorkerPool::worker_loop() {
  unsigned seen = 0;
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    wake_.wait(lock, [&] { return stop_ || generation_ != seen; });
    if (stop_) return;
    seen = generation_;
    ++busy_;
    run_chunk(lock);
    --busy_;
    done_.notify_all();
  }
}

void WorkerPool::parallel_for(size_t n, const std::function<void(size_t)>& fn) {
  if (workers_.empty() || n <= 1) {
    for (size_t i = 0; i < n; ++i) fn(i);
    return;
  }
  // Callers on different threads (metric SLAM and TSBI in live mode) take
  // turns: the pool runs one loop at a time.
  std::lock_guard<std::mutex> turn(call_mutex_);
  std::unique_lock<std::mutex> lock(mutex_);
  job_ = &fn;
  n_ = n;
  next_ = 0;
  error_ = nullptr;
  ++generation_;
  wake_.notify_all();
  run_chunk(lock);
  done_.wait(lock, [&] { return busy_ == 0; });
  job_ = nullptr;
  if (error_) std::rethrow_exception(error_);
}

}  // namespace hmt
