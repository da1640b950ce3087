#include <algorithm>
#include <filesystem>
#include <string>

#include "gz_stream.h"
#include "hmt/common/error.h"
#include "hmt/common/files.h"
#include "hmt/io/rawlog.h"
#include "mrpt_archive.h"
#include "mrpt_fallback.h"
#include "rawlog_collector.h"
#include "rawlog_objects.h"
#include "rawlog_reader.h"

namespace hmt::io {
namespace detail {
namespace {

using Kind = RawObject::Kind;

void add_observation(const RawObject& o, RawlogCollector& collector) {
  if (o.kind == Kind::kScan)
    collector.add_scan(o.scan);
  else if (o.kind == Kind::kOdometry)
    collector.add_odometry(o.pose);
  // Any other observation type is of no use here.
}

void add_entry(const RawObject& o, RawlogCollector& collector,
               bool inside_rawlog) {
  switch (o.kind) {
    case Kind::kNull:
      return collector.empty_entry();
    case Kind::kSensoryFrame:
      for (const RawObject& obs : o.children) add_observation(obs, collector);
      return;
    case Kind::kActionCollection:
      for (const RawObject& a : o.children)
        if (a.kind == Kind::kMove2D) collector.add_move(a.move);
      return;  // other actions (e.g. 3D movements): not used
    case Kind::kRawlog:
      // Very old files hold a whole CRawlog object instead of a sequence.
      if (inside_rawlog) collector.not_an_entry(o.class_name);
      for (const RawObject& inner : o.children)
        add_entry(inner, collector, true);
      return;
    default:
      if (o.base != RawObject::Base::kObservation)
        collector.not_an_entry(o.class_name);
      add_observation(o, collector);
  }
}

class RawlogStream : public LogStream {
 public:
  RawlogStream(const std::string& path, bool chosen_by_content)
      : LogStream(path),
        chosen_by_content_(chosen_by_content),
        file_bytes_(std::filesystem::file_size(path)),
        in_(path),
        archive_(in_),
        collector_(path) {}

  bool next(LogStep& out) override {
    if (mrpt_) return mrpt_->next(out);
    while (!collector_.next_step(out)) {
      if (ended_) return false;
      read_entry();
      if (mrpt_) return mrpt_->next(out);
    }
    ++handed_out_;
    return true;
  }

  double fraction_read() const override {
    if (mrpt_) return mrpt_->fraction_read();
    if (ended_ || file_bytes_ == 0) return 1.0;
    return std::min(1.0, static_cast<double>(in_.file_offset()) / static_cast<double>(file_bytes_));
  }

 private:
  // One top-level object, or the end of the file.
  void read_entry() {
    collector_.set_entry(entry_);
    if (in_.at_end()) {
      collector_.check_clean_end(in_);
      collector_.end_of_file(entry_);
      ended_ = true;
      return;
    }
    RawObject obj;
    try {
      obj = read_object(archive_);
    } catch (const UnknownClassError& e) {
      // Objects carry no length, so the rest of the file cannot be read
      // without knowing this class: MRPT reads the file instead, from its
      // start, and its stream goes on after the steps already handed out
      // (the same ones: the plugin collects with the same RawlogCollector).
      mrpt_ = open_rawlog_with_mrpt(
          source(), chosen_by_content_,
          "a " + e.class_name + " (entry " + std::to_string(entry_) + ")");
      LogStep skipped;
      for (size_t k = 0; k < handed_out_; ++k) mrpt_->next(skipped);
      return;
    } catch (const ArchiveError&) {
      // The clean end was handled by at_end() above, so this is damage.
      collector_.unreadable_entry(in_, chosen_by_content_);
    }
    add_entry(obj, collector_, false);
    ++entry_;
  }

  const bool chosen_by_content_;
  const uint64_t file_bytes_;
  GzInputStream in_;
  ArchiveReader archive_;
  RawlogCollector collector_;
  size_t entry_ = 0;
  size_t handed_out_ = 0;
  bool ended_ = false;
  std::unique_ptr<LogStream> mrpt_;  // the MRPT plugin's stream, once needed
};

}  // namespace

std::unique_ptr<LogStream> open_rawlog(const std::string& path, bool chosen_by_content) {
  require_readable_file(path, "input log");
  if (std::filesystem::file_size(path) == 0)
    throw InputError("input log '" + path + "' is empty");
  return std::make_unique<RawlogStream>(path, chosen_by_content);
}

}  // namespace detail

hmt::Log read_rawlog(const std::string& path) {
  return drain(*detail::open_rawlog(path, false));
}

}  // namespace hmt::io
