// Output files that are either complete or absent: written to a temporary
// sibling and renamed into place, so a failure never leaves a half-written or
// corrupted output behind (and never damages an earlier good one).
#pragma once

#include <functional>
#include <ostream>
#include <string>

namespace hmt {

// Calls fill(stream) on a temporary file, then atomically renames it to
// `path`. Throws OutputError if anything fails; the temporary is removed.
void write_file_atomically(const std::string& path,
                           const std::function<void(std::ostream&)>& fill);
void write_text_atomically(const std::string& path, const std::string& text);

// Removes the temporaries write_file_atomically left in `dir` when its
// process was killed mid-write (NAME.tmp.PID of a process that no longer
// runs); the outputs themselves are whole, old or new. Silent on failure.
void remove_stale_temporaries(const std::string& dir);

// Creates the directory (and parents) or throws OutputError.
void make_directories(const std::string& path);

// Throws InputError("<what> '<path>' does not exist / is not a regular file").
void require_readable_file(const std::string& path, const std::string& what);

}  // namespace hmt
