// The environment map's sampling density for Debug mode: the probabilities
// and the picture of `pathtracer --env-probability`, with a few figures.
#include <algorithm>
#include <functional>

#include "pathtracer/env_probability.h"
#include "viewer/debugger/debugger.h"
#include "viewer/debugger/json_values.h"
#include "viewer/debugger/todo_collector.h"

namespace pt::debug {

namespace {

std::string base64(const std::vector<uint8_t>& bytes) {
  static const char* digits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (size_t i = 0; i < bytes.size(); i += 3) {
    const uint32_t b = uint32_t(bytes[i]) << 16 | (i + 1 < bytes.size() ? uint32_t(bytes[i + 1]) << 8 : 0) |
                       (i + 2 < bytes.size() ? uint32_t(bytes[i + 2]) : 0);
    out += digits[b >> 18 & 63];
    out += digits[b >> 12 & 63];
    out += i + 1 < bytes.size() ? digits[b >> 6 & 63] : '=';
    out += i + 2 < bytes.size() ? digits[b & 63] : '=';
  }
  return out;
}

}  // namespace

EnvironmentDensityResult environment_density(const Scene& scene, const RenderOptions& opts) {
  const auto env = std::find_if(scene.lights.begin(), scene.lights.end(),
                                [](const Light& l) { return l.type == LightType::Environment && l.environment; });
  if (env == scene.lights.end())
    throw InputError("no environment map: choose one under \"environment\" (-e) to see where it is sampled");
  if (opts.part < 3)
    throw InputError("parts 1 and 2 shade normals: the environment map is sampled from part 3 on");
  const EnvironmentMap& map = *env->environment;
  EnvironmentDensityResult r;
  r.part = opts.part;
  r.sampler = opts.part >= 8 ? "importance (part 8)" : "uniform over the sphere";
  r.width = map.width;
  r.height = map.height;
  TodoCollector todos;
  {
    ScopedPathRecorder install(&todos);
    try {
      std::vector<double> p = environment_texel_probabilities(map, opts.part, &r.note);
      for (double x : p) r.total += x;
      if (!p.empty()) {
        r.max_ratio = *std::max_element(p.begin(), p.end()) * double(p.size());
        const size_t top = std::max<size_t>(1, p.size() / 100);
        std::nth_element(p.begin(), p.begin() + ptrdiff_t(top), p.end(), std::greater<double>());
        for (size_t i = 0; i < top; ++i) r.top_share += p[i];
      }
      std::string again;
      r.png = encode_environment_probability_png(map, opts.part, &again);
    } catch (const std::exception& e) {
      r.error = std::string("build_environment_distribution: ") + e.what();
    }
  }
  r.todos = todos.todos;
  return r;
}

Json EnvironmentDensityResult::json() const {
  Json o = json_object();
  o.set("part", json_int(part))
      .set("sampler", json_text(sampler))
      .set("width", json_int(width))
      .set("height", json_int(height))
      .set("total", json_real(total))
      .set("max_ratio", json_real(max_ratio))
      .set("top_share", json_real(top_share))
      .set("note", json_text(note))
      .set("png", json_text(png.empty() ? "" : "data:image/png;base64," + base64(png)))
      .set("todos", json_strings(todos));
  if (!error.empty()) o.set("error", json_text(error));
  return o;
}

}  // namespace pt::debug
