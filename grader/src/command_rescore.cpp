// grader rescore: a graded folder's signatures made again from the renders
// it kept (cases/<case>/render*/render.pfm) and the references, without
// rendering anything. When the signature gains a figure, the known bugs'
// gradings are rescored and the catalogue remade from them
// (make_catalogue.py), instead of grading every mutant again. Verdicts,
// scores and every other figure stay as they were graded.
#include <cstdio>
#include <filesystem>

#include "common/image_io.h"
#include "grader/src/commands.h"
#include "grader/src/grade.h"
#include "grader/src/reference.h"
#include "grader/src/rules.h"
#include "grader/src/scoring.h"
#include "grader/src/signature.h"
#include "grader/src/text.h"

namespace grader {
namespace cli {

namespace fs = std::filesystem;

namespace {

// The renders a case kept, in their graded order (render, render_1, ...).
std::vector<std::string> kept_renders(const fs::path& case_dir) {
  std::vector<std::string> files;
  for (int i = 0;; ++i) {
    const fs::path p = case_dir / (i == 0 ? std::string("render") : "render_" + std::to_string(i)) / "render.pfm";
    if (!fs::is_regular_file(p)) break;
    files.push_back(p.string());
  }
  return files;
}

// The case's result with its image figures made again; false (and the
// result as it was) when it has no image to rescore.
bool rescore_case(const Case& c, const Common& common, const Rules& rules, CaseResult* r) {
  const std::vector<std::string> files = kept_renders(r->dir);
  if (files.empty() || r->signature.count("failed_image") + r->signature.count("mean_ratio") == 0) return false;
  Reference ref;
  std::string why;
  if (!load_reference(common.references, c, &ref, &why)) return false;
  CandidateRenders cand;
  cand.share = render_plan(c, ref.deterministic, rules).share;
  for (const std::string& f : files) {
    cand.images.push_back(pt::read_pfm(f));
    if (cand.images.back().width != ref.mean.width || cand.images.back().height != ref.mean.height) return false;
  }
  const ImageScore img = score_renders(cand, ref.mean, ref.variance, ref.runs, case_score_options(c, ref, rules));
  for (const auto& [key, value] : image_signature(mean_of(cand.images), ref.mean, img)) r->signature[key] = value;
  return true;
}

}  // namespace

int command_rescore(const Common& common, const std::vector<std::string>& grade_dirs, const std::string& out) {
  const std::vector<Case> cases = read_cases(common.cases);
  const Rules rules = make_rules(cases, common.references);
  int rescored = 0, kept = 0;
  for (const std::string& d : grade_dirs) {
    if (!fs::is_directory(d + "/cases")) throw std::runtime_error(d + ": not a grader output folder (no cases/)");
    const fs::path target = fs::path(out) / fs::path(d).lexically_normal().filename();
    if (fs::weakly_canonical(target) == fs::weakly_canonical(d))
      throw std::runtime_error(d + ": rescore writes beside it, not over it: give another --out");
    for (const auto& entry : fs::directory_iterator(d + "/cases")) {
      const std::string path = entry.path().string() + "/result.json";
      if (!fs::exists(path)) continue;
      CaseResult r;
      if (!case_result_from_json(pt::read_json_file(path), &r)) throw std::runtime_error(path + ": not a case result");
      r.dir = entry.path().string();
      const auto c = std::find_if(cases.begin(), cases.end(), [&](const Case& k) { return k.name == r.c.name; });
      // A case no longer in the list keeps its figures.
      const bool done = c != cases.end() && rescore_case(*c, common, rules, &r);
      rescored += done;
      kept += !done;
      const fs::path case_out = target / "cases" / entry.path().filename();
      fs::create_directories(case_out);
      write_text((case_out / "result.json").string(), case_result_json(r));
    }
  }
  std::printf("rescore: %d case signatures made again, %d kept as graded, into %s\n", rescored, kept, out.c_str());
  return kAllPassed;
}

}  // namespace cli
}  // namespace grader
