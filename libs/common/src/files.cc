#include "hmt/common/files.h"

#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "hmt/common/error.h"

namespace hmt {
namespace fs = std::filesystem;

// A temporary's name: the output's, this infix, the writing process's id
// (remove_stale_temporaries reads it back).
constexpr char kTempInfix[] = ".tmp.";

void write_file_atomically(const std::string& path,
                           const std::function<void(std::ostream&)>& fill) {
  const std::string tmp = path + kTempInfix + std::to_string(::getpid());
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw OutputError("cannot create output file '" + tmp + "'");
    errno = 0;
    try {
      fill(out);
    } catch (...) {
      out.close();
      std::remove(tmp.c_str());
      throw;
    }
    out.flush();
    if (!out) {
      // The failed write's reason ("No space left on device", "File too
      // large"), when the stream left one.
      const int err = errno;
      out.close();
      std::remove(tmp.c_str());
      throw OutputError("failed writing output file '" + path + "'" +
                        (err ? std::string(": ") + std::strerror(err) : std::string()));
    }
  }
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) {
    std::remove(tmp.c_str());
    throw OutputError("cannot move output into place at '" + path +
                      "': " + ec.message());
  }
}

void write_text_atomically(const std::string& path, const std::string& text) {
  write_file_atomically(path, [&](std::ostream& os) { os << text; });
}

void remove_stale_temporaries(const std::string& dir) {
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    const size_t at = name.rfind(kTempInfix);
    const size_t digits = at + sizeof kTempInfix - 1;
    if (at == std::string::npos || digits >= name.size()) continue;
    const std::string pid = name.substr(digits);
    if (pid.find_first_not_of("0123456789") != std::string::npos || pid.size() > 9) continue;
    // kill(pid, 0) fails with ESRCH when no such process runs.
    if (::kill(static_cast<pid_t>(std::stol(pid)), 0) == 0 || errno != ESRCH) continue;
    std::error_code rm;
    fs::remove(it->path(), rm);
  }
}

void make_directories(const std::string& path) {
  std::error_code ec;
  fs::create_directories(path, ec);
  if (ec || !fs::is_directory(path))
    throw OutputError("cannot create output directory '" + path +
                      "'" + (ec ? ": " + ec.message() : std::string()));
}

void require_readable_file(const std::string& path, const std::string& what) {
  std::error_code ec;
  if (!fs::exists(path, ec))
    throw InputError(what + " '" + path + "' does not exist");
  if (!fs::is_regular_file(path, ec))
    throw InputError(what + " '" + path + "' is not a regular file");
  std::ifstream f(path, std::ios::binary);
  if (!f) throw InputError(what + " '" + path + "' cannot be opened for reading");
}

}  // namespace hmt
