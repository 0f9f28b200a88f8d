#include "viewer/overlays.h"

#include <algorithm>
#include <cstring>
#include <functional>

#include "grader/src/grade.h"
#include "common/image_io.h"
#include "grader/src/pictures.h"
#include "grader/src/reference.h"
#include "grader/src/signature.h"
#include "common/json.h"
#include "viewer/requests.h"

namespace pt::viewer {

namespace {

// Pixel i of a w x h image (row 0 at the bottom) coloured into rows from the top.
std::vector<uint8_t> flip_to_rgb(int w, int h, const std::function<void(size_t i, uint8_t rgb[3])>& colour) {
  std::vector<uint8_t> out(size_t(w) * h * 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) colour(size_t(y) * w + x, &out[(size_t(h - 1 - y) * w + x) * 3]);
  return out;
}

std::string pfm_header(const Frame& f) {
  return "PF\n" + std::to_string(f.width) + " " + std::to_string(f.height) + "\n-1\n";
}

}  // namespace

std::vector<uint8_t> frame_rgb(const Frame& f) {
  return flip_to_rgb(f.width, f.height, [&](size_t i, uint8_t out[3]) {
    const Color c = f.color(i);
    out[0] = radiance_to_byte(c.x);
    out[1] = radiance_to_byte(c.y);
    out[2] = radiance_to_byte(c.z);
  });
}

std::vector<uint8_t> frame_png(const Frame& f) { return encode_png_rgb(frame_rgb(f), f.width, f.height); }

size_t frame_pfm_size(const Frame& f) { return pfm_header(f).size() + f.pixels() * 12; }

void frame_pfm_bytes(const Frame& f, size_t offset, size_t n, char* out) {
  // encode_pfm's bytes: the header, then each pixel's three floats, rows
  // from the bottom (the payload's order).
  const std::string head = pfm_header(f);
  for (; n > 0 && offset < head.size(); --n) *out++ = head[offset++];
  for (size_t k = offset - head.size(); n > 0;) {
    const size_t within = k % 12, m = std::min(12 - within, n);
    std::memcpy(out, &f.payload[(k / 12) * 20 + within], m);
    out += m;
    k += m;
    n -= m;
  }
}

Overlay frame_overlay(const Frame& f, const std::string& kind, int target) {
  const int w = f.width, h = f.height;
  Overlay o;
  if (kind == "render" || kind.empty()) {
    o.rgb = frame_rgb(f);
  } else if (kind == "rate") {
    target = std::max(1, target);
    o.rgb = flip_to_rgb(w, h, [&](size_t i, uint8_t out[3]) {
      uint32_t n;
      std::memcpy(&n, &f.payload[i * 20 + 12], 4);
      rate_to_rgb(float(n) / float(f.samples > 0 ? f.samples : target), out);
    });
  } else if (kind == "tests") {
    double& scale = o.scale;
    for (size_t i = 0; i < size_t(w) * h; ++i) scale = std::max(scale, double(f.tests(i)));
    o.rgb = flip_to_rgb(w, h, [&](size_t i, uint8_t out[3]) {
      rate_to_rgb(scale > 0 ? float(f.tests(i) / scale) : 0.0f, out);
    });
  } else {
    throw BadRequest("kind: expected render, rate or tests");
  }
  return o;
}

std::string difference_pending(const Frame& f, const RenderOptions& opts, const ViewerCase& vc) {
  const int want = vc.opts.samples_per_pixel;
  if (opts.cell_set || f.samples >= want || image_key(opts) != image_key(vc.opts)) return "";
  return "difference shown when the render reaches " + std::to_string(want) + " samples (now " +
         std::to_string(f.samples) + ")";
}

Difference difference_overlay(const Frame& f, const RenderOptions& opts, const ViewerCase& vc,
                              const std::string& reference_dir, const grader::Catalogue& catalogue,
                              const grader::CaseGroups& groups) {
  const std::string& name = vc.c.name;
  RenderOptions shown = opts;
  shown.samples_per_pixel = f.samples;
  if (image_key(shown) != image_key(vc.opts) || opts.cell_set)
    throw BadRequest("this render's settings are not case " + name + "'s: apply the case's settings first", 409);
  grader::Reference ref;
  std::string why;
  if (!grader::load_reference(reference_dir, vc.c, &ref, &why)) throw BadRequest(name + ": " + why, 404);
  const int w = f.width, h = f.height;
  if (ref.mean.width != w || ref.mean.height != h) throw BadRequest(name + ": the reference is another size", 409);
  const ImageBuffer mine = f.image();
  int fx = 0, fy = 0;
  if (const int bad = grader::count_non_finite(mine, &fx, &fy))
    throw BadRequest(std::to_string(bad) + " pixels are NaN or infinite", 422);
  const grader::ImageScore sc =
      grader::score_image(mine, ref.mean, ref.variance, ref.runs, grader::case_score_options(vc.c, ref));
  // Deterministic references measure |c - m| in tolerances: 1 is the limit.
  const double threshold = sc.deterministic ? 1.0 : sc.pixel_threshold;
  const grader::Picture pic = grader::error_picture(sc.pixel_z, w, h, threshold);
  Difference d;
  d.picture.rgb = std::vector<uint8_t>(pic.rgb.begin(), pic.rgb.end());
  d.picture.scale = threshold;
  d.verdict = (sc.passed ? "matches the reference: " : "differs from the reference: ") + sc.summary();
  d.differs = !sc.passed;
  d.hints_known = !catalogue.bugs.empty();
  if (d.differs && d.hints_known) {
    // The case's signature as grade_case records it for a failed image.
    grader::CaseSignature figures;
    figures.failed = true;
    figures.figures = grader::image_signature(mine, ref.mean, sc);
    figures.figures["failed_image"] = 1;
    d.hints = grader::likely_bugs_for_case(name, figures, catalogue, groups);
  }
  return d;
}

std::string hints_json(const Difference& d) {
  std::string s = "{\"hints\":[";
  for (size_t i = 0; i < d.hints.size(); ++i) {
    const grader::KnownBug& bug = *d.hints[i].bug;
    auto [readme, section] = grader::readme_section(bug.readme);
    // A Markdown heading's `code` marks are not words.
    section.erase(std::remove(section.begin(), section.end(), '`'), section.end());
    s += std::string(i ? "," : "") + "{\"text\":" + json_quote(d.hints[i].words) +
         ",\"function\":" + json_quote(bug.function) + ",\"file\":" + json_quote(bug.file) +
         ",\"readme\":" + json_quote(readme) + ",\"section\":" + json_quote(section) + "}";
  }
  s += "]";
  if (d.differs && d.hints_known && d.hints.empty()) s += std::string(",\"note\":") + json_quote(grader::kNoHintClose);
  return s + "}";
}

}  // namespace pt::viewer
