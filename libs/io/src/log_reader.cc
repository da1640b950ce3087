#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

#include "hmt/common/error.h"
#include "hmt/common/files.h"
#include "hmt/io/log_reader.h"
#include "hmt/io/log_stream.h"
#include "rawlog_reader.h"
#include "rosbag_reader.h"
#include "text_file.h"

namespace hmt::io {
namespace {

// Message names of CARMEN logs (carmen/src/logger), any of which may open one.
constexpr std::string_view kCarmenMessages[] = {
    "FLASER",     "RLASER",      "LASER3",      "LASER4",     "RAWLASER1",
    "RAWLASER2",  "RAWLASER3",   "RAWLASER4",   "ROBOTLASER1", "ROBOTLASER2",
    "ODOM",       "TRUEPOS",     "PARAM",       "SYNC",       "NMEAGGA",
    "NMEARMC",    "SONAR",       "BUMPER",      "SCANMARK",   "POSITIONLASER",
    "IMU",        "VECTORMOVE",  "ROBOTVELOCITY", "BASEVELOCITY",
    "FOLLOWTRAJECTORY", "GPSNMEA", "OLDLASER",  "REARLASER",  "FRONTLASER"};

bool looks_like_carmen(std::string_view head) {
  const size_t start = head.find_first_not_of(" \t\r\n");
  if (start == std::string_view::npos) return false;
  head.remove_prefix(start);
  if (head[0] == '#') return true;
  const size_t end = head.find_first_of(" \t\r\n");
  const std::string_view first = head.substr(0, end);
  for (std::string_view m : kCarmenMessages)
    if (first == m) return true;
  return false;
}

// The first line of a ROS bag, any version ("#ROSBAG V2.0\n").
constexpr std::string_view kBagMagic = "#ROSBAG V";

bool starts_with(const std::string& s, std::string_view prefix) {
  return s.compare(0, prefix.size(), prefix) == 0;
}

}  // namespace

LogFormat detect_log_format(const std::string& path) {
  require_readable_file(path, "input log");
  if (std::filesystem::file_size(path) == 0)
    throw InputError("input log '" + path + "' is empty");
  // The bag's magic line first: it starts with '#', as CARMEN comments do.
  const std::string head = detail::read_file_head(path, 4096);
  if (starts_with(head, kBagMagic)) {
    std::ifstream in(path, std::ios::binary);
    std::string raw(kBagMagic.size(), '\0');
    in.read(raw.data(), static_cast<std::streamsize>(raw.size()));
    if (!starts_with(raw, kBagMagic))
      throw InputError("input log '" + path +
                       "' is a gzip-compressed ROS bag: decompress it first (rosbag reads "
                       "plain files only)");
    return LogFormat::kRosBag;
  }
  // A rawlog starts with a binary object header, so a few KB of text that
  // begin with a CARMEN message are decisive.
  return looks_like_carmen(head) ? LogFormat::kCarmen : LogFormat::kRawlog;
}

std::unique_ptr<LogStream> open_log(const std::string& path, const BagOptions& bag) {
  switch (detect_log_format(path)) {
    case LogFormat::kCarmen:
      return open_carmen(path);
    case LogFormat::kRosBag:
      return detail::open_bag(path, bag);
    case LogFormat::kRawlog:
      break;
  }
  return detail::open_rawlog(path, /*chosen_by_content=*/true);
}

hmt::Log read_log(const std::string& path, const BagOptions& bag) {
  return drain(*open_log(path, bag));
}

}  // namespace hmt::io
