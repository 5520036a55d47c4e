#include "io/json_file.h"

#include <algorithm>

#include "io/atomic_file.h"
#include "io/input_file.h"

namespace skidsim::io {

nlohmann::json read_json_file(const std::string& path, const char* what) {
  const std::string text = read_input_file(path, kMaxJsonBytes, what);
  // nlohmann stops quietly at a NUL: whatever follows would go unread.
  if (const std::size_t at = text.find('\0'); at != std::string::npos)
    throw InputError(path + ":" + std::to_string(1 + std::count(text.begin(), text.begin() + static_cast<long>(at), '\n')) +
                     ": a NUL byte at byte " + std::to_string(at) + " (not a JSON text file)");
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    // nlohmann gives the byte it stopped at (1-based) and a message that
    // starts with its own error code: keep the reason, add the line.
    const std::size_t at = std::min<std::size_t>(e.byte, text.size());
    const long line = 1 + std::count(text.begin(), text.begin() + static_cast<long>(at), '\n');
    std::string reason = e.what();
    if (reason.rfind("[json.exception.", 0) == 0 && reason.find("] ") != std::string::npos)
      reason = reason.substr(reason.find("] ") + 2);
    throw InputError(path + ":" + std::to_string(line) + ": invalid JSON at byte " + std::to_string(e.byte) + ": " +
                     reason);
  } catch (const nlohmann::json::exception& e) {
    // A number past double's range ("1e999") is refused as it is parsed.
    throw InputError(path + ": invalid JSON: " + e.what());
  }
}

}  // namespace skidsim::io
