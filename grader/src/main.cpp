// grader: renders the canonical cases with any pathtracer build, scores them
// against the committed references and writes the reports. See
// grader/README.md for the commands, the scoring and the exit codes. The
// commands themselves are in commands.cpp, commands_references.cpp and
// command_calibrate.cpp.
#include <CLI/CLI.hpp>
#include <cstdio>

#include "grader/src/commands.h"

using namespace grader::cli;

namespace {

// Every command's own options, with their defaults.
struct Options {
  std::string out = "grader_out";  // run, merge
  uint64_t seed = 1;
  bool quiet = false;
  int runs = 64;  // make-references
  bool force = false;
  std::string work = "build/grader_work";  // make-references, calibrate
  int retime = 0;
  bool costs_only = false;
  int seeds = 50;  // calibrate
  std::vector<std::string> builds;  // calibrate: NAME=PATH
  uint64_t first_seed = 2000;
  std::string table = source_dir() + "/grader/tables/calibration.md";
  std::string compare_case, compare_out = ".";
  std::vector<std::string> compare_files;  // compare
  bool list = false;
  std::vector<std::string> shard_dirs;  // merge
  bool leave_one_out = false;  // hints
  std::vector<std::string> graded;
  std::vector<std::string> grade_dirs;  // rescore
  std::string rescore_out;
  std::string hints_table = source_dir() + "/grader/tables/hints.md";
  int max_part = 9;  // functions
  std::string functions_out = "grader_functions";
};

CLI::App* add_run(CLI::App& app, Common& common, Options& o) {
  CLI::App* run = app.add_subcommand("run", "Grade a build: render every case, score, write the reports");
  common.add_to(run, true);
  common.add_sandbox_to(run);
  run->add_option("-o,--out", o.out, "Output folder")->capture_default_str();
  run->add_option("--seed", o.seed, "Seed of the candidate's renders")->capture_default_str();
  run->add_flag("-q,--quiet", o.quiet, "No line per case while grading");
  return run;
}

CLI::App* add_make_references(CLI::App& app, Common& common, Options& o) {
  CLI::App* make = app.add_subcommand("make-references", "Render the references with the reference build (slow)");
  common.add_to(make, true);
  make->add_option("--runs", o.runs, "Independent renders per case")->check(CLI::Range(2, 100000))->capture_default_str();
  make->add_flag("--force", o.force, "Remake references that already match their case");
  make->add_option("--work", o.work, "Scratch folder")->capture_default_str();
  CLI::Option* retime = make->add_option("--retime", o.retime,
                   "Only re-measure the recorded render times (median of N renders, one at a time; -j ignored) and costs")
      ->check(CLI::Range(1, 1000));
  make->add_flag("--costs-only", o.costs_only,
                 "With --retime: re-measure only the costs per query (as the grader renders each case), keep the times")
      ->needs(retime);
  return make;
}

CLI::App* add_calibrate(CLI::App& app, Common& common, Options& o) {
  CLI::App* calibrate = app.add_subcommand("calibrate", "Grade correct builds at many seeds: false-failure rates");
  common.add_to(calibrate, true);
  calibrate->add_option("--seeds", o.seeds, "Seeds per case")->check(CLI::Range(1, 100000))->capture_default_str();
  calibrate->add_option("--first-seed", o.first_seed, "The first seed")->capture_default_str();
  calibrate->add_option("--build", o.builds,
                        "NAME=PATH: another correct build to calibrate beside --pathtracer (a legal variant's "
                        "pathtracer); repeatable");
  calibrate->add_option("--table", o.table, "Where the table goes")->capture_default_str();
  calibrate->add_option("--work", o.work, "Scratch folder")->capture_default_str();
  return calibrate;
}

CLI::App* add_compare(CLI::App& app, Common& common, Options& o) {
  CLI::App* compare = app.add_subcommand(
      "compare", "Compare your render of a case (PFM or PNG) with its reference; --list prints the cases' commands");
  compare->add_option("case", o.compare_case, "The case your render is of (see --list)");
  compare->add_option("files", o.compare_files,
                      "Your render: a .pfm (full statistics) or a .png (8-bit comparison); several .pfm renders at "
                      "different seeds are judged with their own noise, as grader run does");
  compare->add_flag("--list", o.list, "Print every case with the command that renders it");
  compare->add_option("-o,--out", o.compare_out, "Where compare_CASE.png and .html go")->capture_default_str();
  compare->add_option("--cases", common.cases, "The case list")->capture_default_str();
  compare->add_option("--references", common.references, "The reference folder")->capture_default_str();
  compare->add_option("--scenes", common.scenes, "Where the cases' scenes are")->capture_default_str();
  compare->add_option("--catalogue", common.catalogue, "The known bugs' signatures, for the likely causes")
      ->capture_default_str();
  return compare;
}

CLI::App* add_hints(CLI::App& app, Common& common, Options& o) {
  CLI::App* hints = app.add_subcommand(
      "hints", "Measure the hints on the known bugs (each left out, each function's left out), or give graded folders' hints");
  hints->add_option("--catalogue", common.catalogue, "The known bugs' signatures")->capture_default_str();
  hints->add_option("--cases", common.cases, "The case list (the cases' groups)")->capture_default_str();
  hints->add_flag("--leave-one-out", o.leave_one_out,
                  "Match each bug against the others, and each function's bugs against the other functions' (the default)");
  hints->add_option("--graded", o.graded, "Print the hints of these `grader run` output folders instead (no table)");
  hints->add_option("--references", common.references, "With --graded: the reference folder (its probes.json)")
      ->capture_default_str();
  hints->add_option("--table", o.hints_table, "Where the table goes")->capture_default_str();
  return hints;
}

CLI::App* add_functions(CLI::App& app, Common& common, Options& o) {
  CLI::App* f = app.add_subcommand(
      "functions", "Call each function you write on fixed inputs and compare its answers with the reference's");
  f->add_option("--pathtracer", common.pathtracer, "The pathtracer binary to check")->capture_default_str();
  f->add_option("--references", common.references, "The reference folder (its probes.json)")->capture_default_str();
  f->add_option("--part", o.max_part, "Check the functions of parts 1 to N")->check(CLI::Range(1, 9))->capture_default_str();
  f->add_option("-o,--out", o.functions_out, "Where the build's answers go")->capture_default_str();
  return f;
}

CLI::App* add_merge(CLI::App& app, Common& common, Options& o) {
  CLI::App* merge = app.add_subcommand("merge", "Join the outputs of several shards into one set of reports");
  merge->add_option("-o,--out", o.out, "Output folder")->capture_default_str();
  merge->add_option("--cases", common.cases, "The case list (for the order)")->capture_default_str();
  merge->add_option("shards", o.shard_dirs, "Output folders of `grader run --shard`")->required();
  return merge;
}

CLI::App* add_rescore(CLI::App& app, Common& common, Options& o) {
  CLI::App* rescore = app.add_subcommand(
      "rescore", "Make graded folders' signatures again from their kept renders and the references (no rendering)");
  rescore->add_option("grade_dirs", o.grade_dirs, "Output folders of `grader run`")->required();
  rescore->add_option("-o,--out", o.rescore_out, "Where each folder's rescored cases/<case>/result.json go")
      ->required();
  rescore->add_option("--cases", common.cases, "The case list")->capture_default_str();
  rescore->add_option("--references", common.references, "The reference folder")->capture_default_str();
  return rescore;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"grader: scores a pathtracer build against the reference images"};
  app.require_subcommand(1);
  Common common;
  Options o;
  CLI::App* run = add_run(app, common, o);
  CLI::App* make = add_make_references(app, common, o);
  CLI::App* calibrate = add_calibrate(app, common, o);
  CLI::App* compare = add_compare(app, common, o);
  CLI::App* merge = add_merge(app, common, o);
  CLI::App* hints = add_hints(app, common, o);
  CLI::App* rescore = add_rescore(app, common, o);
  CLI::App* functions = add_functions(app, common, o);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : kUsageError;
  }
  try {
    if (*run) return command_run(common, o.out, o.seed, o.quiet);
    if (*make) return command_make_references(common, o.runs, o.force, o.retime, o.costs_only, o.work);
    if (*calibrate) {
      std::vector<Build> builds;
      for (const std::string& b : o.builds) {
        const size_t eq = b.find('=');
        if (eq == std::string::npos || eq == 0 || eq + 1 == b.size())
          throw std::runtime_error("--build " + b + ": expected NAME=PATH");
        builds.push_back({b.substr(0, eq), b.substr(eq + 1)});
      }
      return command_calibrate(common, builds, o.seeds, o.first_seed, o.table, o.work + "/calibrate");
    }
    if (*merge) return command_merge(common, o.out, o.shard_dirs);
    if (*hints) return command_hints(common, o.hints_table, o.graded);
    if (*functions) return command_functions(common, o.max_part, o.functions_out);
    if (*rescore) return command_rescore(common, o.grade_dirs, o.rescore_out);
    if (*compare) return command_compare(common, o.list, o.compare_case, o.compare_files, o.compare_out);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "grader: %s\n", e.what());
    return kUsageError;
  }
  return kUsageError;
}
