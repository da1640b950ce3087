#include "mrpt_fallback.h"

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <stdexcept>
#include <system_error>

#include "hmt/common/error.h"
#include "mrpt_plugin_abi.h"
#include "plugin_loader.h"

#ifndef HMT_IO_MRPT_PLUGIN_PATH
#error "HMT_IO_MRPT_PLUGIN_PATH must name the plugin's build location"
#endif

namespace hmt::io::detail {
namespace {

std::atomic<size_t> g_fallback_reads{0};

const MrptRawlogPlugin& load_plugin(const std::string& path, const std::string& needed_for) {
  std::string tried;
  const auto get = reinterpret_cast<GetMrptRawlogPluginFn>(
      load_plugin_symbol(kMrptPluginEnv, kMrptPluginFileName, HMT_IO_MRPT_PLUGIN_PATH,
                         kMrptRawlogPluginSymbol, tried));
  if (!get)
    throw InputError("rawlog '" + path + "' holds " + needed_for +
                     ", which only MRPT can read, and the MRPT reader plugin "
                     "cannot be loaded (" + tried + ")");
  return *get();
}

// A plugin function's outcome, as the exception it stands for.
void check(PluginStatus status, const std::string& path, const std::string& error) {
  throw_unless_ok(status, error, [&] { return "reading rawlog '" + path + "' with MRPT"; });
}

// The plugin's cursor as a stream; the cursor (the file, MRPT's objects) is
// closed as soon as the log ends, or fails: MRPT is not asked to read on
// from damage it met (its deserializers do not check everything), a later
// call throws the same error again.
class MrptRawlogStream : public LogStream {
 public:
  MrptRawlogStream(const std::string& path, bool chosen_by_content, const std::string& needed_for)
      : LogStream(path),
        plugin_(load_plugin(path, needed_for)),
        cursor_(nullptr, Close{&plugin_}) {
    ++g_fallback_reads;
    MrptRawlogCursor* cursor = nullptr;
    std::string error;
    check(plugin_.open(path.c_str(), chosen_by_content, &cursor, &error), path, error);
    cursor_.reset(cursor);
    std::error_code ec;  // 0 (progress reads as done) if the size is unknown
    const std::uintmax_t size = std::filesystem::file_size(path, ec);
    file_bytes_ = ec ? 0 : size;
  }

  bool next(LogStep& out) override {
    if (failed_) std::rethrow_exception(failed_);
    if (!cursor_) return false;
    bool got = false;
    std::string error;
    try {
      check(plugin_.next(cursor_.get(), &out, &got, &error), source(), error);
    } catch (...) {
      failed_ = std::current_exception();
      cursor_.reset();
      throw;
    }
    if (!got) cursor_.reset();
    return got;
  }

  double fraction_read() const override {
    if (!cursor_ || file_bytes_ == 0) return 1.0;
    return std::min(1.0, static_cast<double>(plugin_.file_offset(cursor_.get())) /
                             static_cast<double>(file_bytes_));
  }

 private:
  struct Close {
    const MrptRawlogPlugin* plugin;
    void operator()(MrptRawlogCursor* c) const { plugin->close(c); }
  };

  const MrptRawlogPlugin& plugin_;
  std::unique_ptr<MrptRawlogCursor, Close> cursor_;
  uint64_t file_bytes_ = 0;
  std::exception_ptr failed_;
};

}  // namespace

std::unique_ptr<LogStream> open_rawlog_with_mrpt(const std::string& path, bool chosen_by_content,
                                                 const std::string& needed_for) {
  return std::make_unique<MrptRawlogStream>(path, chosen_by_content, needed_for);
}

hmt::Log read_rawlog_with_mrpt(const std::string& path, bool chosen_by_content,
                               const std::string& needed_for) {
  return drain(*open_rawlog_with_mrpt(path, chosen_by_content, needed_for));
}

size_t mrpt_fallback_reads() { return g_fallback_reads; }

}  // namespace hmt::io::detail
