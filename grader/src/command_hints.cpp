// `grader hints`: how often the report's likely causes name the right bug,
// measured on the catalogue of known bugs (each bug left out in turn, and
// each function's bugs left out together), written to tables/hints.md; or,
// given graded folders, the likely causes of each.
#include <cstdio>
#include <filesystem>

#include "grader/src/commands.h"
#include "grader/src/hints.h"
#include "grader/src/text.h"

namespace grader {
namespace cli {

namespace fs = std::filesystem;

namespace {

int print_folder_hints(const Catalogue& cat, const CaseGroups& groups, const std::vector<std::string>& graded) {
  for (const std::string& dir : graded) {
    if (graded.size() > 1) std::printf("== %s\n", dir.c_str());
    for (const std::string& line : hint_lines_for_folder(dir, cat, groups)) std::printf("%s\n", line.c_str());
  }
  return kAllPassed;
}

}  // namespace

int command_hints(const Common& common, const std::string& table, const std::vector<std::string>& graded) {
  const Catalogue cat = read_catalogue(common.catalogue);
  const CaseGroups groups = case_groups(read_cases(common.cases));
  if (!graded.empty()) return print_folder_hints(cat, groups, graded);
  HintRates by_bug, by_function;
  const std::string bug_rows = held_out_table(cat, groups, HoldOut::Bug, &by_bug);
  const std::string function_rows = held_out_table(cat, groups, HoldOut::Function, &by_function);
  const std::string s =
      "<!-- REFERENCE ONLY: measured on the mutants; the starter kit leaves this table out -->\n"
      "# Hints: does the grader name the right bug?\n\n"
      "Each known bug of the catalogue (`grader/known_bugs.json`: the mutants of `instructors/mutants/`, graded at "
      "commit " + cat.commit + ") is matched against the rest of it, as a student's build would be: up to three "
      "hints, one per function, nearest first, none farther than " + fmt("%.2f", kHintDistance) +
      ". Goals: the right function first for at least 80 % of the bugs and among the first three for at least "
      "90 %; the right part among the first three for at least 95 %. The bugs the catalogue was never made from "
      "are measured apart (`instructors/mutants/held_out/held_out.md`).\n\n"
      "Made by `grader hints --leave-one-out` at commit " + git_commit() + " on " + utc_now() + ".\n\n"
      "## Each bug left out\n\n"
      "The bug alone is left out; the other bugs of its function stay, as a new bug of a function the catalogue "
      "knows would find them.\n\n" +
      bug_rows +
      "\n## Each function's bugs left out\n\n"
      "Every bug of the bug's function is left out, as for a bug of a function the catalogue has no bug of: no "
      "hint can name that function, so the right function is never named; what is measured is whether the hints "
      "still point at the right part.\n\n" +
      function_rows;
  if (!table.empty()) {
    fs::create_directories(fs::path(table).parent_path());
    write_text(table, s);
  }
  std::printf("%s", s.c_str());
  return by_bug.function_top3 >= 0.8 && by_bug.part_top3 >= 0.95 ? kAllPassed : kSomeFailed;
}

}  // namespace cli
}  // namespace grader
