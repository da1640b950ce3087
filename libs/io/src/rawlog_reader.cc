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

}  // namespace

hmt::Log read_rawlog(const std::string& path, bool chosen_by_content) {
  require_readable_file(path, "input log");
  if (std::filesystem::file_size(path) == 0)
    throw InputError("input log '" + path + "' is empty");

  GzInputStream in(path);
  ArchiveReader archive(in);
  RawlogCollector collector(path);
  size_t entry = 0;
  for (;; ++entry) {
    collector.set_entry(entry);
    if (in.at_end()) {
      collector.check_clean_end(in);
      break;
    }
    RawObject obj;
    try {
      obj = read_object(archive);
    } catch (const UnknownClassError& e) {
      // Objects carry no length, so the rest of the file cannot be read
      // without knowing this class: MRPT reads the whole file instead.
      return read_rawlog_with_mrpt(
          path, chosen_by_content,
          "a " + e.class_name + " (entry " + std::to_string(entry) + ")");
    } catch (const ArchiveError&) {
      // The clean end was handled by at_end() above, so this is damage.
      collector.unreadable_entry(in, chosen_by_content);
    }
    add_entry(obj, collector, false);
  }
  return collector.finish(entry);
}

}  // namespace detail

hmt::Log read_rawlog(const std::string& path) {
  return detail::read_rawlog(path, false);
}

}  // namespace hmt::io
