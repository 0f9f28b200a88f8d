// Small text helpers the grader's commands and reports share.
#pragma once
#include <string>

namespace grader {

// printf of one double: fmt("%.2f s", 1.5) == "1.50 s" (so never %d).
std::string fmt(const char* format, double v);
// "42 s", "3.5 min".
std::string fmt_seconds(double s);
// The current time, "2026-11-21T18:30:00Z".
std::string utc_now();
// Writes `text` to `path` through a temporary file and a rename. Throws
// std::runtime_error naming the file.
void write_text(const std::string& path, const std::string& text);

}  // namespace grader
