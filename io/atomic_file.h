// Whole-file writes that never leave a half-written result: the content goes
// to a temporary file beside the target, which is renamed over it only once
// it is complete and flushed.
#pragma once

#include <functional>
#include <stdexcept>
#include <string>

namespace skidsim::io {

// Calls `write(tmp_path)` to produce the file, then renames tmp_path to
// `path`. If `write` throws, the temporary is removed and `path` is untouched.
void write_atomically(const std::string& path, const std::function<void(const std::string&)>& write);

// Convenience for text content.
void write_text_atomically(const std::string& path, const std::string& text);

// Thrown for bad input files; what() names the file and, where known, the
// line and field.
struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace skidsim::io
