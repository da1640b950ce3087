// One process of the framework (002 Sec. V): a thread that takes messages
// from its bounded inbox, in order, and hands each to its handler.
//
// Life cycle: construct (nothing runs), start() (the thread starts; nothing
// after it can fail half-way), post() messages, stop() (the inbox is closed,
// what is in it is still handled, the thread is joined). The destructor
// stops. A handler that throws ends the process: the first exception is
// kept for error(), the inbox is closed (so posters never wait on it) and
// on_failure runs, which lets the owner close the other queues too.
#pragma once

#include <exception>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <utility>

#include "hmt/framework/bounded_queue.h"

namespace hmt::framework {

template <class Msg>
class Process {
 public:
  using Handler = std::function<void(Msg&)>;

  Process(std::string name, size_t capacity, Handler handler,
          std::function<void()> on_failure = {})
      : name_(std::move(name)),
        inbox_(capacity),
        handler_(std::move(handler)),
        on_failure_(std::move(on_failure)) {}
  ~Process() { stop(); }
  Process(const Process&) = delete;
  Process& operator=(const Process&) = delete;

  void start() {
    if (!thread_.joinable()) thread_ = std::thread([this] { run(); });
  }

  // Waits while the inbox is full; false when the process is stopped or
  // failed (the message is dropped).
  bool post(Msg m) { return inbox_.push(std::move(m)); }

  // Takes no more messages and drops those waiting; the message being
  // handled finishes. Does not join (callable from any thread).
  void abort() { inbox_.close(/*discard=*/true); }

  // Handles what is already in the inbox, then joins. Idempotent.
  void stop() {
    inbox_.close();
    if (thread_.joinable()) thread_.join();
  }

  std::exception_ptr error() const {
    std::lock_guard<std::mutex> lock(error_mutex_);
    return error_;
  }
  const std::string& name() const { return name_; }

 private:
  void run() {
    while (std::optional<Msg> m = inbox_.pop()) {
      try {
        handler_(*m);
      } catch (...) {
        {
          std::lock_guard<std::mutex> lock(error_mutex_);
          error_ = std::current_exception();
        }
        inbox_.close();
        if (on_failure_) on_failure_();
        return;
      }
    }
  }

  const std::string name_;
  BoundedQueue<Msg> inbox_;
  Handler handler_;
  std::function<void()> on_failure_;
  std::thread thread_;
  mutable std::mutex error_mutex_;  // guards error_
  std::exception_ptr error_;
};

}  // namespace hmt::framework
