// How a function of one of hmt_io's plugins (MRPT, ROS bags) ended. An
// exception must not cross the plugin boundary, so the plugin turns it into
// a status and a message (plugin_status_of) and the reader turns them back
// (throw_unless_ok): a bad file stays an hmt::InputError, anything else a
// failure. Both plugins are built with the rest of the project, so the
// type crosses as it is.
#pragma once

#include <exception>
#include <stdexcept>
#include <string>

#include "hmt/common/error.h"

namespace hmt::io::detail {

// kInputError: the file is bad (the message is the hmt::InputError's one
// line); kFailure: something else failed (the message says what).
enum class PluginStatus : int { kOk = 0, kInputError = 1, kFailure = 2 };

// Runs `read` inside a plugin, saying how it ended.
template <class Read>
PluginStatus plugin_status_of(std::string* error, Read&& read) {
  try {
    read();
    return PluginStatus::kOk;
  } catch (const InputError& e) {
    *error = e.what();
    return PluginStatus::kInputError;
  } catch (const std::exception& e) {
    *error = e.what();
    return PluginStatus::kFailure;
  }
}

// The exception a plugin function's outcome stands for: an InputError with
// the plugin's message, or a runtime_error saying what was being done
// (`failing()`, built only then) and the message.
template <class Failing>
void throw_unless_ok(PluginStatus status, const std::string& error, Failing&& failing) {
  switch (status) {
    case PluginStatus::kOk:
      return;
    case PluginStatus::kInputError:
      throw InputError(error);
    case PluginStatus::kFailure:
      break;
  }
  throw std::runtime_error(failing() + ": " + error);
}

}  // namespace hmt::io::detail
