#include "viewer/http_helpers.h"

#include <fstream>
#include <sstream>

namespace pt::viewer {

void send_json(httplib::Response& res, const std::string& body, int status) {
  res.status = status;
  res.set_content(body, "application/json");
  res.set_header("Cache-Control", "no-store");
}

void send_error(httplib::Response& res, const std::string& message, int status) {
  send_json(res, "{\"error\":" + json_quote(message) + "}", status);
}

Json body_json(const httplib::Request& req) {
  try {
    return pt::parse_json(req.body, "request");
  } catch (const std::exception& e) {
    throw BadRequest(std::string("malformed JSON: ") + e.what());
  }
}

uint64_t param_u64(const httplib::Request& req, const char* key) {
  const std::string v = req.get_param_value(key);
  if (v.empty() || v.size() > 19 || v.find_first_not_of("0123456789") != std::string::npos)
    throw BadRequest(std::string(key) + ": expected a non-negative integer");
  return std::stoull(v);
}

bool read_file(const std::string& path, std::string* out) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  std::ostringstream s;
  s << in.rdbuf();
  *out = s.str();
  return true;
}

}  // namespace pt::viewer
