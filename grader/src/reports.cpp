#include "grader/src/reports.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "common/image_io.h"
#include "grader/src/findings.h"
#include "grader/src/text.h"

namespace grader {

namespace {

// "-" for figures that were not measured.
std::string opt(const char* f, double v) { return v < 0 ? "-" : fmt(f, v); }

// Width in characters, not bytes (messages hold a few UTF-8 symbols).
size_t text_width(const std::string& s) {
  size_t chars = 0;
  for (unsigned char ch : s)
    if ((ch & 0xC0) != 0x80) ++chars;
  return chars;
}

std::string pad(const std::string& s, size_t width, bool right = false) {
  const size_t chars = text_width(s);
  if (chars >= width) return s;
  const std::string fill(width - chars, ' ');
  return right ? fill + s : s + fill;
}

double total(const std::vector<CaseResult>& rs, bool max) {
  double t = 0;
  for (const auto& r : rs) t += max ? r.max_score : r.score;
  return t;
}

std::string base64_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return "";
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const unsigned n = (unsigned char)bytes[i] << 16 | (unsigned char)bytes[i + 1] << 8 | (unsigned char)bytes[i + 2];
    out += table[n >> 18 & 63], out += table[n >> 12 & 63], out += table[n >> 6 & 63], out += table[n & 63];
  }
  if (i + 1 == bytes.size()) {
    const unsigned n = (unsigned char)bytes[i] << 16;
    out += table[n >> 18 & 63], out += table[n >> 12 & 63], out += "==";
  } else if (i + 2 == bytes.size()) {
    const unsigned n = (unsigned char)bytes[i] << 16 | (unsigned char)bytes[i + 1] << 8;
    out += table[n >> 18 & 63], out += table[n >> 12 & 63], out += table[n >> 6 & 63], out += '=';
  }
  return out;
}

std::string html_escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

}  // namespace

namespace {

// "0.42x" below 100, "1234x" above: the render time over the reference's.
std::string time_ratio(double v) { return v < 0 ? "-" : v < 100 ? fmt("%.2fx", v) : fmt("%.0fx", v); }

// Lays out rows in columns as wide as their widest cell, two spaces apart;
// `right` says which columns are right-aligned (numbers). The last column
// is left as it is (free text).
std::string columns(const std::vector<std::vector<std::string>>& rows, const std::vector<bool>& right) {
  std::vector<size_t> width(right.size(), 0);
  for (const auto& row : rows)
    for (size_t i = 0; i + 1 < row.size() && i < width.size(); ++i) width[i] = std::max(width[i], text_width(row[i]));
  std::string out;
  for (const auto& row : rows) {
    std::string line;
    for (size_t i = 0; i < row.size(); ++i) {
      const bool last = i + 1 == row.size();
      line += last ? row[i] : pad(row[i], width[i], right[i]);
      if (!last) line += "  ";
    }
    while (!line.empty() && line.back() == ' ') line.pop_back();
    out += line + "\n";
  }
  return out;
}

}  // namespace

std::string findings_text(const std::vector<CaseResult>& rs, const std::vector<std::string>& hints) {
  std::string s;
  for (const std::string& f : run_findings(rs)) s += "Noticed: " + f + "\n";
  // The likely causes are the whole build's: say which cases they explain
  // (those that lost points, but for a part not written yet).
  std::vector<std::string> lost;
  for (const CaseResult& r : rs)
    if (r.verdict == Verdict::Failed && !doomed_by_todo(r)) lost.push_back(r.c.name);
  if (!hints.empty() && !lost.empty()) {
    const size_t shown = std::min<size_t>(lost.size(), 8);
    std::string names;
    for (size_t i = 0; i < shown; ++i) names += (i ? ", " : "") + lost[i];
    if (shown < lost.size()) names += fmt(" and %.0f more", double(lost.size() - shown));
    s += "For the cases that lost points (" + names + "):\n";
  }
  for (const std::string& h : hints) s += h + "\n";
  return s;
}

// The relMSE column. relMSE is relative to m^2 + 0.01, so where a passing
// image holds fireflies (a near-mirror metal that sees the light) it is
// large for any render, the reference's too: it is then set beside what
// the renders' own noise gives, so that it does not read as a failure.
static std::string relmse_cell(const CaseResult& r) {
  if (r.verdict == Verdict::Passed && r.relmse > 1.0 && r.relmse_noise > 0)
    return fmt("%.3g", r.relmse) + fmt(" (noise %.3g)", r.relmse_noise);
  return opt("%.4f", r.relmse);
}

std::string terminal_table(const std::vector<CaseResult>& rs, const std::vector<std::string>& hints) {
  std::vector<std::vector<std::string>> rows;
  rows.push_back({"part", "case", "verdict", "score", "relMSE", "time", "time ratio", "detail"});
  for (const auto& r : rs) {
    const std::string detail = r.verdict == Verdict::Passed ? r.metric : r.message;
    rows.push_back({std::to_string(r.c.part), r.c.name, verdict_name(r.verdict),
                    fmt("%.2f", r.score) + "/" + fmt("%g", r.max_score), relmse_cell(r),
                    fmt("%.1f s", r.seconds), time_ratio(r.speed_ratio), detail});
  }
  std::ostringstream s;
  s << columns(rows, {true, false, false, true, true, true, true, false});
  // One line per part: how far the build has got.
  s << "\n";
  for (int part = 1; part <= 9; ++part) {
    int cases = 0, passed = 0, missing = 0;
    double score = 0, max = 0;
    for (const auto& r : rs) {
      if (r.c.part != part) continue;
      ++cases;
      passed += r.verdict == Verdict::Passed;
      missing += doomed_by_todo(r);
      score += r.score;
      max += r.max_score;
    }
    if (cases == 0) continue;
    s << "Part " << part << ": " << passed << "/" << cases << " cases passed, " << fmt("%.2f", score) << " / "
      << fmt("%g", max) << " points" << (missing ? fmt(" (%.0f not implemented)", missing) : "") << "\n";
  }
  int passed = 0;
  for (const auto& r : rs) passed += r.verdict == Verdict::Passed;
  const double t = total(rs, false), m = total(rs, true);
  s << passed << "/" << rs.size() << " cases passed; score " << fmt("%.2f", t) << " / " << fmt("%g", m) << " ("
    << fmt("%.1f", m > 0 ? 100 * t / m : 0) << "%)\n";
  s << "time ratio = the render's time / the reference's recorded time (1.00x = as fast; machines differ)\n";
  const std::string noticed = findings_text(rs, hints);
  if (!noticed.empty()) s << "\n" << noticed;
  return s.str();
}

std::string timing_tables(const std::vector<CaseResult>& rs) {
  std::ostringstream s;
  s << "# Timing\n\n";
  bool any_speedup = false;
  for (const auto& r : rs) any_speedup |= r.c.part == 2;
  if (any_speedup) {
    s << "## Part 2: rendering with and without the BVH\n\n"
      << "| scene | triangles | without BVH (s) | with BVH (s) | speed-up | Mrays/s | tests per ray |\n"
      << "|---|---:|---:|---:|---:|---:|---:|\n";
    for (const auto& r : rs) {
      if (r.c.part != 2) continue;
      s << "| " << r.c.scene << " | " << opt("%.0f", r.triangles) << " | " << opt("%.3f", r.part1_seconds) << " | "
        << opt("%.3f", r.render_seconds) << " | " << (r.speedup < 0 ? "-" : fmt("%.0f×", r.speedup)) << " | "
        << opt("%.3g", r.mrays_per_second) << " | " << opt("%.1f", r.tests_per_ray) << " |\n";
    }
    s << "\n";
  }
  s << "## Every case\n\n"
    << "| part | case | scene | render (s) | reference (s) | time ratio | Mrays/s | tests per ray | wall (s) |\n"
    << "|---:|---|---|---:|---:|---:|---:|---:|---:|\n";
  for (const auto& r : rs)
    s << "| " << r.c.part << " | " << r.c.name << " | " << r.c.scene << " | " << opt("%.3f", r.render_seconds)
      << " | " << opt("%.3f", r.reference_seconds) << " | " << time_ratio(r.speed_ratio)
      << " | " << opt("%.3g", r.mrays_per_second) << " | " << opt("%.1f", r.tests_per_ray) << " | "
      << fmt("%.2f", r.seconds) << " |\n";
  return s.str();
}

namespace {

// "a hidden case of part 3" for a hidden case's name.
std::string hidden_label(const CaseResult& r) { return "a hidden case of part " + std::to_string(r.c.part); }

// Text shown to students with every hidden case's name replaced by
// hidden_label().
std::string without_hidden_names(std::string text, const std::vector<CaseResult>& rs) {
  for (const CaseResult& r : rs) {
    if (!r.c.hidden) continue;
    for (size_t at; (at = text.find(r.c.name)) != std::string::npos;) text.replace(at, r.c.name.size(), hidden_label(r));
  }
  return text;
}

// A hidden case's verdict for students: its message with the case's
// settings taken out (an option and its values, the scene, the files it
// names) and no figures line, command or render output.
std::string hidden_verdict(const CaseResult& r) {
  std::string m = r.message;
  const auto erase_all = [&m](const std::string& what) {
    if (what.empty()) return;
    for (size_t at; (at = m.find(what)) != std::string::npos;) m.replace(at, what.size(), "...");
  };
  erase_all(r.c.scene);
  for (size_t i = 0; i < r.c.options.size(); ++i) {
    if (r.c.options[i].empty() || r.c.options[i][0] != '-') continue;
    std::string flag = r.c.options[i];
    size_t j = i + 1;
    for (; j < r.c.options.size() && !(r.c.options[j][0] == '-' && !std::isdigit((unsigned char)r.c.options[j][1])); ++j)
      flag += " " + r.c.options[j];
    erase_all(flag);
    for (size_t k = i + 1; k < j; ++k)
      if (r.c.options[k].find('.') != std::string::npos && !std::isdigit((unsigned char)r.c.options[k][0]))
        erase_all(r.c.options[k]);  // a file name
  }
  return std::string(verdict_name(r.verdict)) + ": " + m;
}

Json extra_data(const CaseResult& r) {
  using pt::json_real;
  Json extra = pt::json_object(true);
  extra.set("case", pt::json_text(r.c.name))
      .set("hidden", pt::json_bool(r.c.hidden))
      .set("score", json_real(r.score))
      .set("max_score", json_real(r.max_score))
      .set("seconds", json_real(r.seconds))
      .set("render_seconds", json_real(r.render_seconds))
      .set("reference_seconds", json_real(r.reference_seconds))
      .set("speed_ratio", json_real(r.speed_ratio))
      .set("relmse", json_real(r.relmse))
      .set("tests_per_ray", json_real(r.tests_per_ray));
  return extra;
}

// A case's whole output: verdict, figures, command, the render's output.
std::string case_output(const CaseResult& r) {
  std::string output = std::string(verdict_name(r.verdict)) + ": " + r.message;
  if (!r.metric.empty()) output += "\n" + r.metric;
  output += "\nCommand: " + r.command;
  if (r.verdict != Verdict::Passed && !r.log.empty()) output += "\nOutput of the render:\n" + r.log;
  return output;
}

Json test_json(const std::string& name, const std::string& number, const std::string& output, const char* visibility,
               const Json& extra) {
  Json test = pt::json_object();
  test.set("name", pt::json_text(name))
      .set("number", pt::json_text(number))
      .set("output", pt::json_text(output))
      .set("visibility", pt::json_text(visibility))
      .set("extra_data", extra);
  return test;
}

void set_score(Json& test, double score, double max_score, bool passed) {
  test.set("score", pt::json_real(score))
      .set("max_score", pt::json_real(max_score))
      .set("status", pt::json_text(passed ? "passed" : "failed"));
}

}  // namespace

std::string gradescope_json(const std::vector<CaseResult>& rs, const RunInfo& info) {
  std::vector<Json> tests;
  // The cases students may see, one test each.
  for (size_t i = 0; i < rs.size(); ++i) {
    const CaseResult& r = rs[i];
    if (r.c.hidden) continue;
    Json test = test_json("Part " + std::to_string(r.c.part) + ": " + r.c.name,
                          std::to_string(r.c.part) + "." + std::to_string(i + 1), case_output(r), "visible",
                          extra_data(r));
    set_score(test, r.score, r.max_score, r.verdict == Verdict::Passed);
    tests.push_back(test);
  }
  // The hidden cases: per part, one visible test with their total and each
  // one's verdict (no name, no settings); per case, one test for the staff
  // only, with everything.
  std::map<int, std::vector<const CaseResult*>> hidden;
  std::set<int> parts_losing_public_points;
  for (const CaseResult& r : rs) {
    if (r.c.hidden) hidden[r.c.part].push_back(&r);
    else if (r.verdict != Verdict::Passed) parts_losing_public_points.insert(r.c.part);
  }
  std::vector<std::string> staff_notes;
  for (const auto& [part, list] : hidden) {
    double score = 0, max_score = 0;
    std::string output;
    bool all_passed = true;
    for (size_t k = 0; k < list.size(); ++k) {
      const CaseResult& r = *list[k];
      score += r.score;
      max_score += r.max_score;
      all_passed = all_passed && r.verdict == Verdict::Passed;
      output += "Hidden case " + std::to_string(k + 1) + ": " + fmt("%.2f", r.score) + "/" + fmt("%g", r.max_score) +
                ", " + without_hidden_names(hidden_verdict(r), rs) + "\n";
    }
    output = "Cases the starter kit does not have (other viewpoints, scenes and settings), graded by the same rules.\n" +
             output;
    Json extra = pt::json_object(true);
    extra.set("hidden", pt::json_bool(true)).set("part", pt::json_real(part)).set("cases", pt::json_real(double(list.size())));
    Json test = test_json("Part " + std::to_string(part) + ": hidden cases (" + std::to_string(list.size()) + ")",
                          std::to_string(part) + ".99", output, "visible", extra);
    set_score(test, score, max_score, all_passed);
    tests.push_back(test);
    if (!parts_losing_public_points.count(part) && max_score > 0 && score < 0.5 * max_score)
      staff_notes.push_back("Part " + std::to_string(part) + ": every public case passes, but the hidden cases score " +
                            fmt("%.2f", score) + " of " + fmt("%g", max_score) +
                            " (a build that fits the public cases only, or replays their references?)");
  }
  for (const CaseResult& r : rs) {
    if (!r.c.hidden) continue;
    Json test = test_json("Staff only: part " + std::to_string(r.c.part) + " hidden case " + r.c.name,
                          std::to_string(r.c.part) + ".h", case_output(r), "hidden", extra_data(r));
    test.set("status", pt::json_text(r.verdict == Verdict::Passed ? "passed" : "failed"));
    tests.push_back(test);
  }
  if (!staff_notes.empty()) {
    std::string text;
    for (const std::string& n : staff_notes) text += n + "\n";
    Json extra = pt::json_object(true);
    extra.set("staff_note", pt::json_bool(true));
    Json note = test_json("Staff note", "0.0", text, "hidden", extra);
    tests.push_back(note);
  }
  const bool any_hidden = !hidden.empty();
  const std::string findings = findings_text(rs, info.hints);
  Json results = pt::json_object();
  results.set("score", pt::json_real(total(rs, false)))
      .set("output", pt::json_text(without_hidden_names(
          "Graded " + std::to_string(rs.size()) + " cases in " + fmt("%.0f", info.wall_seconds) + " s." +
              (findings.empty() ? std::string() : "\n" + findings),
          rs)))
      .set("visibility", pt::json_text("visible"))
      // The grader's console names every case: hidden from students when
      // some cases are.
      .set("stdout_visibility", pt::json_text(any_hidden ? "hidden" : "visible"))
      .set("tests", pt::json_array(tests));
  return pt::write_json(results);
}

std::string html_report(const std::vector<CaseResult>& rs, const RunInfo& info) {
  std::ostringstream s;
  const double t = total(rs, false), m = total(rs, true);
  s << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n<title>Grading report</title>\n<style>\n"
       "body{font-family:system-ui,sans-serif;margin:2em;max-width:75em;color:#222}\n"
       "table{border-collapse:collapse}td,th{padding:.25em .6em;border-bottom:1px solid #ddd;text-align:left}\n"
       ".passed{color:#16702e;font-weight:bold}.failed{color:#b3261e;font-weight:bold}.error{color:#8a5a00;font-weight:bold}\n"
       ".case{border:1px solid #ccc;border-radius:6px;padding:1em;margin:1.5em 0}\n"
       ".imgs{display:flex;gap:1em;flex-wrap:wrap}.imgs figure{margin:0}.imgs img{width:256px;image-rendering:pixelated;border:1px solid #999}\n"
       "code,pre{background:#f4f4f4;padding:.1em .3em}pre{max-height:12em;overflow:auto;white-space:pre-wrap}\n"
       "</style></head><body>\n";
  s << "<h1>Grading report</h1>\n<p>Binary: <code>" << html_escape(info.pathtracer) << "</code>; started "
    << html_escape(info.started) << "; " << fmt("%.0f", info.wall_seconds) << " s; seed " << info.seed << ".</p>\n";
  s << "<p><strong>Score " << fmt("%.2f", t) << " / " << fmt("%g", m) << " (" << fmt("%.1f", m > 0 ? 100 * t / m : 0)
    << "%)</strong></p>\n";
  for (const std::string& f : run_findings(rs)) s << "<p class=\"noticed\"><strong>Noticed:</strong> " << html_escape(f) << "</p>\n";
  for (const std::string& h : info.hints) s << "<p class=\"hint\">" << html_escape(h) << "</p>\n";
  s << "<table><tr><th>part</th><th>case</th><th>verdict</th><th>score</th><th>relMSE</th><th>time</th><th>time ratio</th><th>detail</th></tr>\n";
  for (const auto& r : rs)
    s << "<tr><td>" << r.c.part << "</td><td><a href=\"#" << r.c.name << "\">" << r.c.name << "</a></td><td class=\""
      << verdict_name(r.verdict) << "\">" << verdict_name(r.verdict) << "</td><td>" << fmt("%.2f", r.score) << "/"
      << fmt("%g", r.max_score) << "</td><td>" << relmse_cell(r) << "</td><td>" << fmt("%.1f s", r.seconds)
      << "</td><td>" << time_ratio(r.speed_ratio) << "</td><td>"
      << html_escape(r.verdict == Verdict::Passed ? r.metric : r.message) << "</td></tr>\n";
  s << "</table>\n";
  for (const auto& r : rs) {
    s << "<div class=\"case\" id=\"" << r.c.name << "\"><h2>Part " << r.c.part << ": " << r.c.name << " <span class=\""
      << verdict_name(r.verdict) << "\">" << verdict_name(r.verdict) << "</span></h2>\n";
    s << "<p>" << html_escape(r.message) << "</p>\n";
    if (!r.metric.empty()) s << "<p>" << html_escape(r.metric) << "</p>\n";
    s << "<p><code>" << html_escape(r.command) << "</code></p>\n";
    const std::string cand = base64_file(r.dir + "/candidate.png"), ref = base64_file(r.dir + "/reference.png"),
                      err = base64_file(r.dir + "/error.png");
    if (!cand.empty() || !ref.empty()) {
      s << "<div class=\"imgs\">";
      const auto fig = [&](const std::string& data, const char* caption) {
        if (!data.empty())
          s << "<figure><img alt=\"" << caption << "\" src=\"data:image/png;base64," << data << "\"><figcaption>"
            << caption << "</figcaption></figure>";
      };
      fig(cand, "candidate");
      fig(ref, "reference (mean)");
      fig(err, "|z| per pixel (red: beyond the threshold)");
      s << "</div>\n";
    }
    if (r.verdict != Verdict::Passed && !r.log.empty()) s << "<pre>" << html_escape(r.log) << "</pre>\n";
    s << "</div>\n";
  }
  s << "</body></html>\n";
  return s.str();
}

void write_reports(const std::string& dir, const std::vector<CaseResult>& rs, const RunInfo& info) {
  write_text(dir + "/report.txt", terminal_table(rs, info.hints));
  write_text(dir + "/timing.md", timing_tables(rs));
  write_text(dir + "/results.json", gradescope_json(rs, info));
  write_text(dir + "/report.html", html_report(rs, info));
}

}  // namespace grader
