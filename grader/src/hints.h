// Hints: the known bugs whose signatures are closest to a graded build's.
//
// The catalogue (grader/known_bugs.json, made from the mutants by
// instructors/mutants/make_catalogue.py) holds, for every known bug, where
// it lives (part, function, file, the README section to read), a hint in a
// student's words, and its signature on every case: which cases it fails
// and how (signature.h). A build's signature is compared with each bug's
// over the cases either fails; the closest bugs, at most one per function,
// become the report's hints, with the build's own figures put into their
// words. Hints never hold solution code, and a build that fails nothing
// gets none.
#pragma once
#include <functional>
#include <memory>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "grader/src/case_result.h"
#include "grader/src/probes.h"
#include "grader/src/signature.h"

namespace grader {

// One case as the hints see it: whether it lost points, and its signature.
struct CaseSignature {
  bool failed = false;
  Signature figures;
};
using BuildSignature = std::map<std::string, CaseSignature>;  // by case name

struct KnownBug {
  std::string name;
  int part = 0;
  std::string function, file, readme;  // readme: "stages/part4_global_illumination/README.md#the-functions-to-write"
  // A student's words, with the build's figures put in: {ratio} the image
  // mean's ratio to the reference's ("x1.9"), {rate} the sample rate's,
  // {tests} the tests per query's, {shadow_rays} shadow rays per query's,
  // {noise} the variance's, each the median over the cases the bug fails.
  std::string hint;
  BuildSignature cases;
  // The functions whose checks (probes.h) the bug's build answered
  // differently from the reference's, when the catalogue was made with
  // them (has_probes): what a build with this bug would be told first.
  bool has_probes = false;
  std::vector<std::string> probes_disagree;
};

struct Catalogue {
  std::string commit, date;
  std::vector<KnownBug> bugs;
  // The parts the tree gives solved (a starter kit's solved_parts.txt): the
  // students did not write them, so no hint names a bug of theirs, nor any
  // function such a bug is in.
  std::set<int> solved_parts;
  // The functions the checks cover (probes.h), when the catalogue was made
  // with them: each bug's build answered all of them, agreeing but for its
  // probes_disagree.
  std::vector<std::pair<std::string, int>> probed_functions;  // function, part
};

// Throws std::runtime_error naming the file when it is missing or malformed.
// Also reads the solved parts of the tree the catalogue is in
// (solved_parts_path(path)), when that file exists.
Catalogue read_catalogue(const std::string& path);

// Where the tree of a catalogue at `catalogue_path` (<root>/grader/known_bugs.json)
// lists the parts it gives solved: <root>/solved_parts.txt.
std::string solved_parts_path(const std::string& catalogue_path);

// solved_parts.txt: lines starting with # are comments, then one part
// number (1-9) a line; blank lines are ignored. A missing file lists none.
// Throws std::runtime_error naming the file and line of anything else.
std::set<int> read_solved_parts(const std::string& path);

// A build's signature from its graded cases.
BuildSignature build_signature(const std::vector<CaseResult>& results);

// What kind of case each is (its part, -H, an open sky, spheres, meshes,
// delta lights, -o 0, adaptive sampling, ...), from the case list: the
// groups whose failing fractions a signature is also compared by, so that
// two bugs that fail different cases of the same kind are near.
using CaseGroups = std::map<std::string, std::vector<std::string>>;  // case name -> its groups
CaseGroups case_groups(const std::vector<Case>& cases);

// How far a build's signature is from a bug's, from 0 (the same) to 1: half
// the mean difference over the cases either fails, half the difference of
// the fractions of each group's cases they fail.
double signature_distance(const BuildSignature& build, const BuildSignature& bug, const CaseGroups& groups);

struct Hint {
  const KnownBug* bug = nullptr;
  double distance = 0;
  // The order the hints come in: the distance, less kOwnPartBonus for a bug
  // of the earliest failing case's part (the thresholds take the distance).
  double rank = 0;
  std::string words;  // the bug's words with the build's figures put in
  std::string text;   // the words, then the function, file and README section, then the cases
  // The build's failing cases the bug fails too: the ones the hint explains.
  std::vector<std::string> cases;
  // A hint from the function checks: the function answered them
  // differently from the reference's. `bug` then points at `checked`, a
  // stand-in for a function the catalogue may have no bug of.
  bool from_probe = false;
  std::shared_ptr<KnownBug> checked;
};

// Hints farther than this say nothing: "no known bug is close" instead.
constexpr double kHintDistance = 0.7;
// Further hints only within this much of the nearest one's distance.
constexpr double kHintSpread = 0.35;
// A bug of the earliest failing case's part ranks as if this much nearer
// (a bug of part k most often fails part k's cases first).
constexpr double kOwnPartBonus = 0.1;

// The lowest part of the build's failing cases (0 when none fails or the
// groups name no part). A case of part k runs stages 1..k only, so a bug
// in a later part cannot have failed it.
int earliest_failing_part(const BuildSignature& build, const CaseGroups& groups);

// A function whose checks disagree is named before any signature's bug:
// the checks call it on known inputs, the signatures only compare images.
// One whose checks agree ranks as if this much farther.
constexpr double kProbeAgreePenalty = 0.3;

// Up to `max_hints` closest known bugs within kHintDistance (and within
// kHintSpread of the nearest), one per function, nearest first; none when the build fails nothing. Bugs of a
// part after earliest_failing_part are named only when no other bug is
// within kHintDistance. No bug of a part the tree gives solved, nor of a
// function of such a part, is named. `exclude`: a bug left out (the
// leave-one-out evaluation). With `probes` (the build's function checks,
// probes.h): the functions that answer them differently come first (those
// whose own checks' callees also disagree after those callees), then the
// signatures' bugs, those of functions whose checks agree ranked
// kProbeAgreePenalty farther. A function of a part no failing case runs
// is not named from its checks.
std::vector<Hint> likely_bugs(const BuildSignature& build, const Catalogue& catalogue, const CaseGroups& groups,
                              int max_hints = 3, const std::string& exclude = "", const ProbeVerdicts* probes = nullptr);
// The same with every bug for which `left_out` is true left out.
std::vector<Hint> likely_bugs_without(const BuildSignature& build, const Catalogue& catalogue,
                                      const CaseGroups& groups, const std::function<bool(const KnownBug&)>& left_out,
                                      int max_hints = 3, const ProbeVerdicts* probes = nullptr);

// What a catalogue bug's build answered to the checks, as verdicts (empty
// when the catalogue was made without them).
ProbeVerdicts catalogued_probes(const KnownBug& bug, const Catalogue& catalogue);

// Hints from one case alone (the viewer's difference overlay, `grader
// compare`): the case's signature against each known bug's on that case
// only; bugs that pass the case are not candidates.
std::vector<Hint> likely_bugs_for_case(const std::string& case_name, const CaseSignature& figures,
                                       const Catalogue& catalogue, const CaseGroups& groups, int max_hints = 3);

// The line that says no known bug is close (the reports, `grader compare`
// and the viewer's difference overlay say it alike).
extern const char* const kNoHintClose;

// "Likely cause N of M: ..." per hint, or kNoHintClose when there are none:
// the same lines wherever hints are shown.
std::vector<std::string> hint_lines(const std::vector<Hint>& hints);

// The report's lines for these results (hint_lines of likely_bugs);
// nothing for a build that fails nothing or an empty catalogue. With the
// build's function checks, then a line "Function check: ..." for each
// function whose checks disagree that a hint may name (of the students'
// parts, and of parts some failing case runs) and no likely cause names.
std::vector<std::string> hint_lines(const std::vector<CaseResult>& results, const Catalogue& catalogue,
                                    const CaseGroups& groups, const ProbeVerdicts* probes = nullptr);

// A README reference of the catalogue ("stages/x/README.md#Section") as
// the file and the section (empty when it names none).
std::pair<std::string, std::string> readme_section(const std::string& readme);

// How the catalogue is measured on bugs it was not made from: each bug is
// matched against the rest with itself left out (Bug), or with every bug of
// its function left out (Function: a family of bugs the catalogue has never
// seen: only its function's checks can name its function). Each bug's own
// answers to the function checks are used when the catalogue has them (a
// build's checks are its own, not learnt from the catalogue); `use_probes`
// false measures the signatures alone.
enum class HoldOut { Bug, Function };

struct HintRates {
  int bugs = 0;
  double function_first = 0, function_top3 = 0, part_top3 = 0;
};

// The table (Markdown) of every caught bug's hints with `hold_out` left out,
// and the rates for Project 3-1, 3-2 and both.
std::string held_out_table(const Catalogue& catalogue, const CaseGroups& groups, HoldOut hold_out,
                           HintRates* rates, bool use_probes = true);

// The hints of a graded folder (`grader run -o DIR`: DIR/cases/*/result.json),
// as its report gives them. Throws naming the folder when it is not one.
// With `references_dir`, the folder's function checks (dir/probes/) are
// compared with the references' too.
std::vector<std::string> hint_lines_for_folder(const std::string& dir, const Catalogue& catalogue,
                                               const CaseGroups& groups, const std::string& references_dir = "");

}  // namespace grader
