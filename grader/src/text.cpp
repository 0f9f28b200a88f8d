#include "grader/src/text.h"

#include <cstdio>
#include <ctime>
#include <vector>

#include "common/image_io.h"

namespace grader {

std::string fmt(const char* format, double v) {
  char buf[256];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

std::string fmt_seconds(double s) {
  return s < 120 ? fmt("%.0f s", s) : fmt("%.1f min", s / 60);
}

std::string utc_now() {
  const std::time_t t = std::time(nullptr);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&t));
  return buf;
}

void write_text(const std::string& path, const std::string& text) {
  pt::write_file_atomically(path, std::vector<uint8_t>(text.begin(), text.end()));
}

}  // namespace grader
