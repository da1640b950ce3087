// Errors that reach the user: one class per cause, each with its own exit code,
// so scripts can tell a bad config from a bad log from a failed write.
#pragma once

#include <stdexcept>
#include <string>

namespace hmt {

enum class ExitCode : int {
  kOk = 0,
  kInternal = 1,  // a bug: an invariant of the program itself failed
  kUsage = 2,     // bad command line
  kConfig = 3,    // malformed, unknown or out-of-range configuration
  kInput = 4,     // missing, truncated or malformed input log / file
  kOutput = 5,    // an output could not be written
  // Stopped by SIGINT or SIGTERM between two scans (128 + SIGINT, as shells
  // report an interrupted command); a checkpoint says where to go on from.
  kInterrupted = 130,
};

class Error : public std::runtime_error {
 public:
  Error(ExitCode code, const std::string& message)
      : std::runtime_error(message), code_(code) {}
  ExitCode code() const { return code_; }

 private:
  ExitCode code_;
};

struct ConfigError : Error {
  explicit ConfigError(const std::string& m) : Error(ExitCode::kConfig, m) {}
};
struct InputError : Error {
  explicit InputError(const std::string& m) : Error(ExitCode::kInput, m) {}
};
struct OutputError : Error {
  explicit OutputError(const std::string& m) : Error(ExitCode::kOutput, m) {}
};
struct InterruptedError : Error {
  explicit InterruptedError(const std::string& m) : Error(ExitCode::kInterrupted, m) {}
};
struct UsageError : Error {
  explicit UsageError(const std::string& m) : Error(ExitCode::kUsage, m) {}
};

}  // namespace hmt
