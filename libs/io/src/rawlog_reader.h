// The rawlog reader with the knowledge of how it was chosen, so that
// read_log() can say "neither a CARMEN log nor a rawlog" for unknown content.
#pragma once

#include <string>

#include "hmt/common/sensor_data.h"

namespace hmt::io::detail {

hmt::Log read_rawlog(const std::string& path, bool chosen_by_content);

}  // namespace hmt::io::detail
