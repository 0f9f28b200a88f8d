#include "grader/src/findings.h"

#include <algorithm>

#include "grader/src/text.h"

namespace grader {

namespace {

double figure(const CaseResult& r, const char* key, double fallback = -1) {
  const auto it = r.signature.find(key);
  return it == r.signature.end() ? fallback : it->second;
}

bool hemisphere_case(const CaseResult& r) {
  return r.command.find(" -H ") != std::string::npos || std::find(r.c.options.begin(), r.c.options.end(), "-H") != r.c.options.end();
}

std::string nan_finding(const std::vector<CaseResult>& rs) {
  const CaseResult* first = nullptr;
  int cases = 0;
  for (const CaseResult& r : rs) {
    if (figure(r, "failure_nan") <= 0) continue;
    ++cases;
    if (!first || r.c.part < first->c.part) first = &r;
  }
  if (!first) return "";
  const double pixels = figure(*first, "nan_pixels");
  return "NaN pixels first appear in part " + std::to_string(first->c.part) + " (" + first->c.name +
         (pixels > 0 ? fmt(", %.0f pixels", pixels) : std::string()) + "; " + std::to_string(cases) +
         (cases == 1 ? " case" : " cases") +
         " in all): a NaN is usually 0/0, such as dividing by a pdf of 0 or normalising a zero vector; the "
         "light samples of this code base always have a positive pdf (stages/part3_direct_lighting/README.md, "
         "\"Conventions that differ from the course's code\")";
}

std::string self_shadowing_finding(const std::vector<CaseResult>& rs) {
  std::vector<const CaseResult*> dim;
  for (const CaseResult& r : rs) {
    if (r.c.part != 3 || r.verdict != Verdict::Failed || hemisphere_case(r)) continue;
    const double all = figure(r, "mean_ratio"), bright = figure(r, "ratio_bright", all), mid = figure(r, "ratio_mid", all);
    const auto half = [](double x) { return x >= 0.3 && x <= 0.7; };
    if (half(all) && half(bright) && half(mid)) dim.push_back(&r);
  }
  if (dim.size() < 2) return "";
  std::string which;
  for (size_t i = 0; i < dim.size() && i < 3; ++i)
    which += (i ? ", " : "") + dim[i]->c.name + fmt(" x%.2f", figure(*dim[i], "mean_ratio"));
  return "part 3's images are about half as bright everywhere (" + which +
         "): self-shadowing? A shadow ray that starts on the surface finds that surface again unless its min_t "
         "is kRayEpsilon; the course's EPS_D (1e-11) is no offset in float rays "
         "(stages/part3_direct_lighting/README.md, \"Conventions that differ from the course's code\")";
}

}  // namespace

std::vector<std::string> run_findings(const std::vector<CaseResult>& rs) {
  std::vector<std::string> out;
  for (const std::string& f : {nan_finding(rs), self_shadowing_finding(rs)})
    if (!f.empty()) out.push_back(f);
  return out;
}

}  // namespace grader
