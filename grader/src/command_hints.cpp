// `grader hints`: how often the report's likely causes name the right bug,
// measured on the catalogue of known bugs (each bug left out in turn, and
// each function's bugs left out together), written to tables/hints.md; or,
// given graded folders, the likely causes of each.
#include <cstdio>
#include <filesystem>

#include "grader/src/commands.h"
#include "grader/src/hints.h"
#include "grader/src/probes.h"
#include "grader/src/text.h"

namespace grader {
namespace cli {

namespace fs = std::filesystem;

namespace {

int print_folder_hints(const Catalogue& cat, const CaseGroups& groups, const std::vector<std::string>& graded,
                       const std::string& references) {
  for (const std::string& dir : graded) {
    if (graded.size() > 1) std::printf("== %s\n", dir.c_str());
    for (const std::string& line : hint_lines_for_folder(dir, cat, groups, references)) std::printf("%s\n", line.c_str());
  }
  return kAllPassed;
}

}  // namespace

int command_hints(const Common& common, const std::string& table, const std::vector<std::string>& graded) {
  const Catalogue cat = read_catalogue(common.catalogue);
  const CaseGroups groups = case_groups(read_cases(common.cases));
  if (!graded.empty()) return print_folder_hints(cat, groups, graded, common.references);
  HintRates by_bug, by_function, alone_bug, alone_function;
  const std::string bug_rows = held_out_table(cat, groups, HoldOut::Bug, &by_bug);
  const std::string function_rows = held_out_table(cat, groups, HoldOut::Function, &by_function);
  // The signatures alone, without the function checks: what they add.
  const std::string alone_bug_rows = held_out_table(cat, groups, HoldOut::Bug, &alone_bug, false);
  const std::string alone_function_rows = held_out_table(cat, groups, HoldOut::Function, &alone_function, false);
  const bool checked = !cat.probed_functions.empty();
  const auto summary = [](const std::string& rows) {
    // The rate lines at the table's end.
    const size_t at = rows.find("\nProject 3-1");
    return at == std::string::npos ? std::string() : rows.substr(at + 1);
  };
  const std::string s =
      "<!-- REFERENCE ONLY: measured on the mutants; the starter kit leaves this table out -->\n"
      "# Hints: does the grader name the right bug?\n\n"
      "Each known bug of the catalogue (`grader/known_bugs.json`: the mutants of `instructors/mutants/`, graded at "
      "commit " + cat.commit + ") is matched against the rest of it, as a student's build would be: up to three "
      "hints, one per function. First the functions whose function checks (`pathtracer --probe`, "
      "`grader functions`) the bug's own build answers differently from the reference's, callees first; then the "
      "nearest signatures, none farther than " + fmt("%.2f", kHintDistance) + ", those of functions whose checks "
      "agree ranked " + fmt("%.2f", kProbeAgreePenalty) + " farther. " +
      (checked ? std::string("Each bug's answers to the checks are its own build's (`instructors/check_functions.sh "
                             "mutants`), never learnt from the others. ")
               : std::string("This catalogue was made without the function checks: the signatures alone. ")) +
      "Goals: the right function first for at least 80 % of the bugs and among the first three for at least "
      "90 %; the right part among the first three for at least 95 %. The bugs the catalogue was never made from "
      "are measured apart (`instructors/mutants/held_out/held_out.md`).\n\n"
      "Made by `grader hints --leave-one-out` at commit " + git_commit() + " on " + utc_now() + ".\n\n"
      "## Each bug left out\n\n"
      "The bug alone is left out; the other bugs of its function stay, as a new bug of a function the catalogue "
      "knows would find them.\n\n" +
      bug_rows + "\nThe signatures alone, without the function checks:\n\n" + summary(alone_bug_rows) +
      "\n## Each function's bugs left out\n\n"
      "Every bug of the bug's function is left out, as for a bug of a function the catalogue has no bug of: no "
      "signature can name that function, only its own checks can; the hints may still point at the right "
      "part.\n\n" +
      function_rows + "\nThe signatures alone, without the function checks:\n\n" + summary(alone_function_rows);
  if (!table.empty()) {
    fs::create_directories(fs::path(table).parent_path());
    write_text(table, s);
  }
  std::printf("%s", s.c_str());
  return by_bug.function_top3 >= 0.8 && by_bug.part_top3 >= 0.95 ? kAllPassed : kSomeFailed;
}

int command_functions(const Common& common, int max_part, const std::string& out) {
  common.check_binary();
  const std::string reference = reference_probes_path(common.references);
  const pt::Json want = pt::read_json_file(reference);
  RunSettings run = common.run_settings();
  std::string failure;
  if (!run_probes(run, max_part, out, &failure))
    throw std::runtime_error(common.pathtracer + " --probe: " + failure + " (its output: " + out + "/stderr.txt)");
  std::string problem;
  const ProbeVerdicts verdicts = compare_probes(want, pt::read_json_file(out + "/probes.json"), &problem);
  if (!problem.empty()) throw std::runtime_error(out + "/probes.json: " + problem);
  int differ = 0;
  for (const auto& [function, v] : verdicts) {
    std::printf("part %d  %-32s %s\n", v.part, function.c_str(), v.agrees ? "agrees" : ("DIFFERS: " + v.detail).c_str());
    differ += !v.agrees;
  }
  std::printf("%d of %zu functions answer the checks as the reference does (parts 1 to %d)\n",
              int(verdicts.size()) - differ, verdicts.size(), max_part);
  return differ == 0 ? kAllPassed : kSomeFailed;
}

}  // namespace cli
}  // namespace grader
