// The run's state to and from a cereal binary archive (checkpoint.h).
#pragma once

#include <cereal/archives/binary.hpp>

#include "hmt/framework/hmt_system.h"

namespace hmt::checkpoint {

void write_state(cereal::BinaryOutputArchive& ar, const framework::HmtSystem& system);
void read_state(cereal::BinaryInputArchive& ar, framework::HmtSystem& system);

}  // namespace hmt::checkpoint
