#include "viewer/access.h"

#include <algorithm>
#include <cctype>

namespace pt::viewer {

namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return s;
}

// Compared in constant time.
bool same_token(const std::string& t, const std::string& token) {
  if (t.size() != token.size() || token.empty()) return false;
  unsigned diff = 0;
  for (size_t i = 0; i < t.size(); ++i) diff |= unsigned(t[i] ^ token[i]);
  return diff == 0;
}

// The value of cookie `name` in a Cookie header ("a=1; b=2"), or "".
std::string cookie_value(const std::string& header, const std::string& name) {
  size_t at = 0;
  while (at < header.size()) {
    while (at < header.size() && (header[at] == ' ' || header[at] == ';')) ++at;
    const size_t end = std::min(header.find(';', at), header.size());
    const std::string pair = header.substr(at, end - at);
    const size_t eq = pair.find('=');
    if (eq != std::string::npos && pair.compare(0, eq, name) == 0) return pair.substr(eq + 1);
    at = end;
  }
  return "";
}

}  // namespace

std::string cookie_name(int port) { return "pt_viewer_" + std::to_string(port); }

Refusal check_request(const httplib::Request& req, const std::string& token, int port) {
  const std::string me = "127.0.0.1:" + std::to_string(port), me_too = "localhost:" + std::to_string(port);
  const std::string url = "open the URL the viewer printed when it started (http://" + me + "/?token=...)";
  const std::string host = lower(req.get_header_value("Host"));
  if (host != me && host != me_too)
    return {403, "refused: the request is addressed to '" + req.get_header_value("Host") + "', not to this viewer (" +
                     me + "): " + url};
  if (req.has_header("Origin")) {
    const std::string origin = lower(req.get_header_value("Origin"));
    if (origin != "http://" + me && origin != "http://" + me_too)
      return {403, "refused: a request made by another site's page (Origin " + req.get_header_value("Origin") +
                       "); the viewer answers its own page only"};
  }
  const bool query_token = req.has_param("token") && same_token(req.get_param_value("token"), token);
  // Sec-Fetch-Site: "same-origin" (the page), "none" (typed or opened by
  // the user), "same-site" (another port), "cross-site".
  const std::string site = lower(req.get_header_value("Sec-Fetch-Site"));
  const bool page_with_token = req.method == "GET" && req.path == "/" && query_token;
  if (!site.empty() && site != "same-origin" && site != "none" && !page_with_token)
    return {403, "refused: a request made by another site's page (Sec-Fetch-Site: " + site +
                     "); the viewer answers its own page only"};
  const bool header_token = req.has_header("X-Token") && same_token(req.get_header_value("X-Token"), token);
  const bool cookie_token = same_token(cookie_value(req.get_header_value("Cookie"), cookie_name(port)), token);
  if (!query_token && !header_token && !cookie_token)
    return {403, "refused: the request does not carry this viewer's token: " + url +
                     " (a tab left open by an earlier viewer needs the new URL)"};
  if (req.method == "POST" || req.method == "PUT" || req.method == "PATCH" || req.method == "DELETE") {
    std::string type = lower(req.get_header_value("Content-Type"));
    type = type.substr(0, type.find(';'));
    while (!type.empty() && type.back() == ' ') type.pop_back();
    if (type != "application/json")
      return {415, "refused: the request's body must be JSON (Content-Type: application/json), not '" +
                       req.get_header_value("Content-Type") + "'"};
  }
  return {};
}

}  // namespace pt::viewer
