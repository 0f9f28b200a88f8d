// Who may talk to the viewer: its own page, or a program holding the
// token, and nothing another site makes a browser send. Checked on every
// request before it is routed (server.cpp).
//
// - The Host header must name the viewer (127.0.0.1:PORT or
//   localhost:PORT): a page of another site whose name is made to point at
//   127.0.0.1 (DNS rebinding) sends its own name.
// - A request a browser sends for another site's page is refused: its
//   Origin is not the viewer's, or its Sec-Fetch-Site says "cross-site" or
//   "same-site" (another port of 127.0.0.1 is the same site, and a
//   SameSite=Strict cookie goes with it). Only the page itself, opened from
//   the printed URL, may navigate to "/" from elsewhere, with the token in
//   the URL.
// - The token: ?token=, the X-Token header, or the cookie the page gets,
//   named after the port (pt_viewer_PORT), so that viewers on several
//   ports do not overwrite each other's.
// - A request with a body (POST) must say it is JSON (Content-Type:
//   application/json): a form or a "no-cors" fetch of another page can
//   send only form and text types without the browser asking first.
#pragma once
#include <string>

#include <httplib.h>

namespace pt::viewer {

// The page's cookie on port `port`.
std::string cookie_name(int port);

// Why `req` is refused (status and a sentence saying what to do), or
// status 0 when it may go on.
struct Refusal {
  int status = 0;
  std::string reason;
};
Refusal check_request(const httplib::Request& req, const std::string& token, int port);

}  // namespace pt::viewer
