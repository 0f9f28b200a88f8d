// Debug mode's routes: a tool's call (debug_api.h) starts in a worker
// process with the page's settings and is answered at once with its job;
// the page follows the job with /api/status (how long it has run, where it
// is stuck) and may stop it with /api/stop, like a render, and then asks
// /api/debug-result for the tool's result, the reason its input was
// refused (400), or how the worker ended (a crash names the function it
// happened in).
#include <mutex>
#include <string>

#include "viewer/debug_api.h"
#include "viewer/http_helpers.h"
#include "viewer/routes.h"

namespace pt::viewer {

namespace {

std::string todo_list(const Job& job) {
  std::string todo = "[";
  for (size_t i = 0; i < job.todo.size(); ++i) todo += (i ? "," : "") + json_quote(job.todo[i]);
  return todo + "]";
}

}  // namespace

void add_debug_routes(httplib::Server& svr, App& app) {
  svr.Post(R"(/api/debug/([a-z]+))", guarded([&](const httplib::Request& req, httplib::Response& res) {
    const std::string tool = req.matches[1];
    if (!is_debug_tool(tool)) throw BadRequest("no debug tool named '" + tool + "'", 404);
    const Json body = body_json(req);
    const Json* in = body.get("debug");
    if (!in || in->type != Json::Type::Object) throw BadRequest("debug: expected the tool's input (an object)");
    auto job = launch_job(app, "debug", body, {tool, write_json(*in)});
    std::lock_guard<std::mutex> lock(job->mu);
    send_json(res, job_json(*job));
  }));
  svr.Get("/api/debug-result", guarded([&](const httplib::Request& req, httplib::Response& res) {
    auto job = find_job(app, req);
    std::lock_guard<std::mutex> lock(job->mu);
    if (job->kind != "debug") throw BadRequest("job " + std::to_string(job->id) + " is not a Debug mode call", 404);
    if (job->state == "running") throw BadRequest("the call is still running", 409);
    const std::string todo = todo_list(*job);
    if (job->state == "done" && job->result_status > 0) {
      // The TODO lines the worker printed (outside the tool's own record), as "worker_todo".
      std::string answer = job->result;
      if (!job->todo.empty() && answer.size() > 2 && answer[0] == '{')
        answer.insert(1, "\"worker_todo\":" + todo + ",");
      return send_json(res, answer, job->result_status);
    }
    // Stopped (409: by the page, by a newer call, or with no page left) or
    // the worker failed or crashed (500).
    send_json(res,
              "{\"error\":" + json_quote(job->message) + ",\"state\":" + json_quote(job->state) + ",\"todo\":" + todo + "}",
              job->state == "cancelled" ? 409 : 500);
  }));
}

}  // namespace pt::viewer
