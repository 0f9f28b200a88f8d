// Debug mode's route: one tool's call (debug_api.h) in a worker process,
// with the page's settings. The answer is the tool's result, the reason its
// input was refused (400), or how the worker ended (a crash names the
// function it happened in).
#include <chrono>
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
    std::unique_lock<std::mutex> lock(job->mu);
    const bool ended =
        job->cv.wait_for(lock, std::chrono::seconds(300), [&] { return job->state != "running" || server_stopping(); });
    const std::string todo = todo_list(*job);
    if (job->state == "done" && job->result_status > 0) {
      // The TODO lines the worker printed (outside the tool's own record), as "worker_todo".
      std::string answer = job->result;
      if (!job->todo.empty() && answer.size() > 2 && answer[0] == '{')
        answer.insert(1, "\"worker_todo\":" + todo + ",");
      return send_json(res, answer, job->result_status);
    }
    const std::string message = !ended                       ? "the debugger took more than 300 s (stopped)"
                                : job->state == "cancelled" ? "replaced by a newer Debug mode call"
                                                            : job->message;
    const int status = job->state == "cancelled" && ended ? 409 : 500;
    const std::string state = job->state;
    lock.unlock();
    if (!ended) app.workers.stop(job);
    send_json(res, "{\"error\":" + json_quote(message) + ",\"state\":" + json_quote(state) + ",\"todo\":" + todo + "}",
              status);
  }));
}

}  // namespace pt::viewer
