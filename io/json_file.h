// Every JSON file skidsim reads (height-map metadata, a run's report.json and
// frames.json, batch reports) is read here: through the checked opener
// (io/input_file.h), with no NUL byte, and parse errors naming the file, the
// line and the byte.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace skidsim::io {

// The parsed file, or InputError naming `path` ("what" says what it is).
nlohmann::json read_json_file(const std::string& path, const char* what);

}  // namespace skidsim::io
