// grader make-references: renders each case's reference with the reference
// build, or (--retime) re-measures the times and costs of existing ones.
#include <cstdio>
#include <filesystem>

#include "grader/src/commands.h"
#include "grader/src/reference.h"

namespace grader {
namespace cli {

namespace fs = std::filesystem;

int command_make_references(const Common& common, int runs, bool force, int retime, const std::string& work) {
  const std::vector<Case> cases = common.select();
  common.check_binary();
  MakeSettings ms;
  ms.run = common.run_settings();
  ms.run.timeout_scale *= 3;  // never lose a long reference run to a tight case timeout
  ms.runs = runs;
  ms.jobs = common.jobs;
  ms.force = force;
  ms.commit = git_commit();
  ms.work_dir = work;
  fs::create_directories(work);
  int failures = 0;
  for (size_t i = 0; i < cases.size(); ++i) {
    // A hidden case's reference goes with the hidden list (--hidden-cases).
    const std::string root = common.references_for(cases[i]);
    fs::create_directories(root);
    std::string message;
    const bool ok = retime > 0 ? retime_reference(root, cases[i], ms, retime, &message)
                               : make_reference(root, cases[i], ms, &message);
    failures += !ok;
    std::printf("[%2zu/%zu] %-24s %s%s\n", i + 1, cases.size(), cases[i].name.c_str(), ok ? "" : "FAILED: ",
                message.c_str());
    std::fflush(stdout);
  }
  return failures ? kSomeFailed : kAllPassed;
}

}  // namespace cli
}  // namespace grader
