// What every route of the viewer's API shares: JSON
// replies and errors, the request's JSON body and numeric parameters, and
// guarded(), which turns a route's BadRequest (requests.h) or failure into
// a JSON error. A file of new routes needs only this header, routes.h and
// the headers of what it serves.
#pragma once
#include <cstdint>
#include <new>
#include <string>

#include <httplib.h>

#include "common/json.h"
#include "viewer/requests.h"

namespace pt::viewer {

void send_json(httplib::Response& res, const std::string& body, int status = 200);
// {"error": message} with `status`.
void send_error(httplib::Response& res, const std::string& message, int status);

// The request's body as JSON (400 when malformed).
Json body_json(const httplib::Request& req);

// The query parameter `key` as a non-negative integer (400 otherwise).
uint64_t param_u64(const httplib::Request& req, const char* key);

// The whole file; false when it cannot be read.
bool read_file(const std::string& path, std::string* out);

// Runs `handler`, turning bad requests and failures into a JSON error.
template <class F>
httplib::Server::Handler guarded(F handler) {
  return [handler](const httplib::Request& req, httplib::Response& res) {
    try {
      handler(req, res);
    } catch (const BadRequest& e) {
      send_error(res, e.what(), e.status);
    } catch (const std::bad_alloc&) {
      send_error(res, "out of memory", 500);
    } catch (const std::exception& e) {
      send_error(res, e.what(), 500);
    }
  };
}

}  // namespace pt::viewer
