#include "hmt/io/log_stream.h"

#include <utility>

namespace hmt::io {
namespace {

// Hands out the steps of a log held whole, moving each out.
class WholeLogStream : public LogStream {
 public:
  explicit WholeLogStream(hmt::Log log) : LogStream(log.source), log_(std::move(log)) {}

  bool next(LogStep& out) override {
    if (next_ >= log_.steps.size()) return false;
    out = std::move(log_.steps[next_++]);
    return true;
  }
  double fraction_read() const override { return 1.0; }
  std::optional<size_t> total_steps() const override { return log_.steps.size(); }

 private:
  hmt::Log log_;
  size_t next_ = 0;
};

}  // namespace

hmt::Log drain(LogStream& stream) {
  hmt::Log log;
  log.source = stream.source();
  LogStep step;
  while (stream.next(step)) log.steps.push_back(std::move(step));
  return log;
}

std::unique_ptr<LogStream> stream_of(hmt::Log log) {
  return std::make_unique<WholeLogStream>(std::move(log));
}

}  // namespace hmt::io
