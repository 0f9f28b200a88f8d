#include "grader/src/compare.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "grader/src/grade.h"
#include "grader/src/image_files.h"
#include "common/image_io.h"
#include "grader/src/pictures.h"
#include "grader/src/reference.h"
#include "grader/src/signature.h"
#include "grader/src/text.h"

namespace grader {

namespace fs = std::filesystem;

void print_case_commands(const std::vector<Case>& cases, const std::string& pathtracer, const std::string& scenes) {
  std::printf("The grading cases and the commands that render them (add -t N for N threads: the image does not\n"
              "depend on it). Then: grader compare CASE CASE.pfm (or CASE.png); the grader judges a Monte Carlo\n"
              "image with several renders at different --seed values: grader compare CASE a.pfm b.pfm c.pfm d.pfm\n\n");
  for (const Case& c : cases) {
    std::string cmd = pathtracer + " --part " + std::to_string(c.part);
    for (size_t i = 0; i < c.options.size(); ++i) {
      const bool names_file = i > 0 && (c.options[i - 1] == "-e" || c.options[i - 1] == "-c");
      // Found beside the case list first, as the grader does (case_input_files).
      std::error_code ec;
      const bool beside_list = names_file && !c.files_dir.empty() && fs::path(c.options[i]).is_relative() &&
                               fs::exists(fs::path(c.files_dir) / c.options[i], ec);
      cmd += " " + (beside_list ? fs::relative(fs::path(c.files_dir) / c.options[i], fs::current_path(ec), ec).string()
                    : names_file ? (fs::path(scenes) / c.options[i]).string()
                                 : c.options[i]);
    }
    cmd += " --seed 1 -f " + c.name + ".png --pfm " + c.name + ".pfm " + (fs::path(scenes) / c.scene).string();
    std::printf("%-22s %s\n", c.name.c_str(), cmd.c_str());
  }
}

namespace {

std::string lower_extension(const std::string& path) {
  std::string e = fs::path(path).extension().string();
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char ch) { return char(std::tolower(ch)); });
  return e;
}

std::string html_text(const std::string& s) {
  std::string out;
  for (char ch : s) out += ch == '<' ? "&lt;" : ch == '>' ? "&gt;" : ch == '&' ? "&amp;" : std::string(1, ch);
  return out;
}

void write_page(const std::string& path, const Case& c, const std::string& file, const std::string& png_name,
                const std::string& verdict, const std::vector<std::string>& lines,
                const std::vector<std::string>& hints) {
  std::string s = "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>" + html_text(c.name) +
                  ": your render and the reference</title>\n<style>body{font-family:system-ui,sans-serif;margin:2em;"
                  "color:#222}img{image-rendering:pixelated;max-width:100%;border:1px solid #999}</style></head><body>\n";
  s += "<h1>" + html_text(c.name) + "</h1>\n<p><code>" + html_text(file) + "</code>: " + html_text(verdict) + "</p>\n";
  for (const std::string& h : hints) s += "<p class=\"hint\">" + html_text(h) + "</p>\n";
  s += "<p><img alt=\"your render, the reference, the difference\" src=\"" + html_text(png_name) +
       "\"></p>\n<p>Left to right: your render, the reference (mean of its renders), the difference.</p>\n<ul>\n";
  for (const std::string& l : lines) s += "<li>" + html_text(l) + "</li>\n";
  s += "</ul>\n<p>Case command: <code>pathtracer " + html_text(case_command(c)) + "</code></p>\n</body></html>\n";
  write_text(path, s);
}

// What comparing a render with its reference found, for the terminal, the
// page and the picture.
struct Comparison {
  std::vector<std::string> lines;
  std::vector<std::string> hints;  // "Likely cause ...", when a PFM differs
  std::string verdict;
  int status = 0;
  Picture yours, difference;
};

// The user's render, refused unless it is a readable .pfm or .png of the
// case's size.
ImageBuffer read_candidate(const Case& c, const Reference& ref, const std::string& file, bool* pfm) {
  std::error_code ec;
  if (!fs::is_regular_file(file, ec)) throw std::runtime_error(file + ": no such file");
  const std::string ext = lower_extension(file);
  if (ext != ".pfm" && ext != ".png") throw std::runtime_error(file + ": expected a .pfm or .png image");
  *pfm = ext == ".pfm";
  const ImageBuffer mine = *pfm ? pt::read_pfm(file) : read_png_image(file);
  if (mine.width != ref.mean.width || mine.height != ref.mean.height)
    throw std::runtime_error(file + ": the image is " + std::to_string(mine.width) + " x " + std::to_string(mine.height) +
                             ", case " + c.name + " renders " + std::to_string(ref.mean.width) + " x " +
                             std::to_string(ref.mean.height) + " (see grader compare --list)");
  return mine;
}

// PFMs get the grader's own image statistics and a verdict.
Comparison compare_pfm(const Case& c, const Reference& ref, const std::vector<std::string>& files,
                       const std::vector<ImageBuffer>& renders, const Rules& rules, const Catalogue& catalogue,
                       const CaseGroups& groups) {
  Comparison r;
  const int w = renders[0].width, h = renders[0].height;
  for (size_t i = 0; i < renders.size(); ++i) {
    int fx = 0, fy = 0;
    if (const int bad = count_non_finite(renders[i], &fx, &fy))
      throw std::runtime_error(files[i] + ": " + std::to_string(bad) + " pixels are NaN or infinite (the first at x=" +
                               std::to_string(fx) + ", y=" + std::to_string(fy) + " from the top)");
  }
  CandidateRenders cand;
  cand.images = renders;
  const ImageScore s = score_renders(cand, ref.mean, ref.variance, ref.runs, case_score_options(c, ref, rules));
  const ImageBuffer mine = mean_of(renders);
  r.verdict = s.passed ? "matches the reference" : "differs from the reference";
  r.status = s.passed ? 0 : 1;
  r.lines.push_back(s.summary());
  if (!s.deterministic)
    r.lines.push_back(renders.size() > 1
                          ? "judged with your renders' own noise (their spread), as grader run judges a build"
                          : "one render: judged with the reference's noise; give " + std::to_string(rules.renders) +
                                " renders at different --seed values to be judged with your own, as grader run does");
  r.lines.push_back(fmt("mean radiance %.4g", s.mean_candidate) + fmt(" (reference %.4g)", s.mean_reference));
  r.lines.push_back("the grader also checks the costs and, for adaptive cases, the sample-rate image: grader run "
                    "--case " + c.name);
  r.yours = radiance_picture(mine);
  r.difference = error_picture(s.pixel_z, w, h, s.pixel_threshold);
  r.lines.push_back(s.deterministic ? "difference: |yours - reference| in units of the round-off tolerance; red "
                                      "beyond it"
                                    : "difference: |z| per pixel, black (0) to white (the threshold); red beyond it");
  if (!s.passed && !catalogue.bugs.empty()) {
    // The case's signature as grade_case records it for a failed image.
    CaseSignature figures;
    figures.failed = true;
    figures.figures = image_signature(mine, ref.mean, s);
    figures.figures["failed_image"] = 1;
    r.hints = hint_lines(likely_bugs_for_case(c.name, figures, catalogue, groups));
  }
  return r;
}

// An 8-bit image clamps and rounds what the statistics need: compare
// bytes, against the byte difference one standard deviation of noise
// makes in the reference.
Comparison compare_png(const Reference& ref, const Picture& reference, const ImageBuffer& mine) {
  Comparison r;
  const int w = mine.width, h = mine.height;
  r.yours.width = w, r.yours.height = h;
  r.yours.rgb.resize(size_t(w) * h * 3);
  std::vector<float> ratio(size_t(w) * h, 0.0f);
  double sum_diff = 0, sum_noise = 0;
  int beyond = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      double worst = 0;
      for (int ch = 0; ch < 3; ++ch) {
        const size_t i = (size_t(y) * w + x) * 3 + ch;
        r.yours.rgb[i] = (unsigned char)value_from_top(mine, x, y, ch);
        const double m = value_from_top(ref.mean, x, y, ch),
                     sd = std::sqrt(std::max(0.0f, value_from_top(ref.variance, x, y, ch)));
        const double noise = std::fabs(double(pt::radiance_to_byte(float(m + sd))) - pt::radiance_to_byte(float(m)));
        const double d = std::fabs(double(value_from_top(mine, x, y, ch)) - reference.rgb[i]);
        sum_diff += d;
        sum_noise += noise;
        worst = std::max(worst, d / (4 * noise + 2));
      }
      ratio[size_t(y) * w + x] = float(worst);
      beyond += worst > 1;
    }
  const double n = 3.0 * w * h;
  r.verdict = "compared in 8 bits (no verdict: render with --pfm for the grader's statistics)";
  r.lines.push_back(fmt("mean |difference| %.2f levels of 255", sum_diff / n) +
                    fmt(", noise alone gives about %.2f", 0.8 * sum_noise / n));
  r.lines.push_back(fmt("%.2f %% of the pixels differ by more than four noise levels (+2)", 100.0 * beyond / (w * h)));
  r.difference = error_picture(ratio, w, h, 1.0);
  r.lines.push_back("difference: the byte difference against four noise levels (+2), black to white; red beyond it");
  return r;
}

}  // namespace

int compare_render(const Case& c, const std::string& references, const std::vector<std::string>& files,
                   const std::string& out_dir, const Rules& rules, const Catalogue& catalogue,
                   const CaseGroups& groups) {
  Reference ref;
  std::string why;
  if (!load_reference(references, c, &ref, &why)) throw std::runtime_error(c.name + ": " + why);
  if (files.empty()) throw std::runtime_error("compare: no render given");
  std::vector<ImageBuffer> renders;
  bool pfm = false;
  for (const std::string& file : files) {
    renders.push_back(read_candidate(c, ref, file, &pfm));
    if (!pfm && files.size() > 1) throw std::runtime_error(file + ": several renders must all be .pfm files");
  }
  const std::string& file = files[0];
  const Picture reference = radiance_picture(ref.mean);
  const Comparison r = pfm ? compare_pfm(c, ref, files, renders, rules, catalogue, groups)
                            : compare_png(ref, reference, renders[0]);

  std::error_code ec;
  fs::create_directories(out_dir, ec);
  if (ec) throw std::runtime_error(out_dir + ": " + ec.message());
  const std::string png_name = "compare_" + c.name + ".png";
  save_picture(out_dir + "/" + png_name, side_by_side({r.yours, reference, r.difference}, 4));
  const std::string page = out_dir + "/compare_" + c.name + ".html";
  write_page(page, c, files.size() > 1 ? file + " and " + std::to_string(files.size() - 1) + " more" : file, png_name,
             r.verdict, r.lines, r.hints);

  std::printf("%s: %s\n", c.name.c_str(), r.verdict.c_str());
  for (const std::string& l : r.lines) std::printf("  %s\n", l.c_str());
  for (const std::string& h : r.hints) std::printf("%s\n", h.c_str());
  std::printf("Pictures: %s/%s (yours | reference | difference), %s\n", out_dir.c_str(), png_name.c_str(), page.c_str());
  return r.status;
}

}  // namespace grader
