#include "grader/src/run_case.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "grader/src/image_files.h"
#include "grader/src/probability_image.h"
#include "common/image_io.h"

namespace grader {

namespace fs = std::filesystem;

void case_resolution(const Case& c, int* width, int* height) {
  *width = 800;
  *height = 600;
  for (size_t i = 0; i + 2 < c.options.size(); ++i)
    if (c.options[i] == "-r") {
      try {
        *width = std::stoi(c.options[i + 1]);
        *height = std::stoi(c.options[i + 2]);
      } catch (...) {
      }
    }
}

int case_int_option(const Case& c, const std::string& flag, int fallback) {
  for (size_t i = 0; i + 1 < c.options.size(); ++i)
    if (c.options[i] == flag) {
      try {
        return std::stoi(c.options[i + 1]);
      } catch (...) {
      }
    }
  return fallback;
}

double stat_ratio(const Json& stats, const char* num, const char* den) {
  const double d = stats.num(den, 0);
  return d > 0 ? stats.num(num, 0) / d : 0.0;
}

int todo_part(const std::string& line) {
  static const std::string prefix = "TODO: implement Part ";
  const size_t at = line.find(prefix);
  if (at == std::string::npos) return 0;
  const size_t digit = at + prefix.size();
  return digit < line.size() && line[digit] >= '1' && line[digit] <= '9' ? line[digit] - '0' : 0;
}

bool todo_dooms(int todo, int case_part) { return todo >= 1 && todo <= case_part && (todo != 2 || case_part == 2); }

namespace {

// The TODO lines of a render's stderr (its first 64 KB), without repeats.
std::vector<std::string> todo_lines(const std::string& stderr_path) {
  std::vector<std::string> lines;
  const std::string text = read_text_sanitized(stderr_path, 64 << 10);
  size_t start = 0;
  while (start < text.size()) {
    size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    std::string line = text.substr(start, end - start);
    start = end + 1;
    const size_t at = line.find("TODO: implement Part ");
    if (at == std::string::npos || todo_part(line) == 0) continue;
    line = line.substr(at, 240);
    if (std::find(lines.begin(), lines.end(), line) == lines.end()) lines.push_back(line);
  }
  return lines;
}

std::string log_excerpt(const std::string& dir) {
  std::string out = read_text_sanitized(dir + "/stdout.txt", 4000);
  const std::string err = read_text_sanitized(dir + "/stderr.txt", 4000);
  if (!err.empty()) out += (out.empty() ? "" : "\n") + std::string("[stderr]\n") + err;
  return out;
}

// Checks an image file's size against the case's.
bool size_matches(const ImageBuffer& img, int w, int h, const std::string& what, std::string* failure) {
  if (img.width == w && img.height == h) return true;
  char buf[200];
  std::snprintf(buf, sizeof buf, "%s is %d x %d, expected %d x %d", what.c_str(), img.width, img.height, w, h);
  *failure = buf;
  return false;
}

// The command line of a render of `c` by `binary` into `out_dir`, with each
// of its input files (`inputs`, from case_input_files) given as
// `path_of(file)`.
template <class PathOf>
std::vector<std::string> render_argv(const RunSettings& s, const Case& c, int part, uint64_t seed,
                                     const std::vector<std::string>& inputs, const std::string& binary,
                                     const std::string& out_dir, PathOf path_of) {
  std::vector<std::string> argv = {binary, "--part", std::to_string(part)};
  size_t next_input = 1;  // inputs[0] is the scene
  for (size_t i = 0; i < c.options.size(); ++i) {
    const bool names_file = i > 0 && (c.options[i - 1] == "-e" || c.options[i - 1] == "-c");
    // An output the grader asks for (a probability case's image, by its
    // file name) goes into out_dir like the render: in a sandbox only
    // out_dir is writable, and only it is read back.
    const bool names_output = i > 0 && c.options[i - 1] == "--env-probability";
    if (names_output) argv.push_back(out_dir + "/" + c.options[i]);
    else argv.push_back(names_file && next_input < inputs.size() ? path_of(inputs[next_input++]) : c.options[i]);
  }
  argv.insert(argv.end(), {"-t", std::to_string(s.threads)});
  argv.insert(argv.end(), {"--seed", std::to_string(seed), "--no-progress", "-f", out_dir + "/render.png", "--pfm",
                           out_dir + "/render.pfm", "--stats-json", out_dir + "/stats.json", path_of(inputs[0])});
  return argv;
}

// The files the grader reads back from a render's folder.
const std::vector<std::string> kRenderFiles = {"render.png", "render.pfm", "render_rate.png", "stats.json",
                                               kProbabilityImageFile};

// Each step below checks one thing about a render's files; false with
// *failure set when it is wrong.

bool output_within_limit(const RunSettings& s, const std::string& abs_dir, std::string* failure) {
  const uint64_t bytes = directory_bytes(abs_dir);
  if (bytes <= s.output_bytes) return true;
  char buf[160];
  std::snprintf(buf, sizeof buf, "wrote %.0f MB, more than the %.0f MB limit", double(bytes) / (1 << 20),
                double(s.output_bytes) / (1 << 20));
  *failure = buf;
  return false;
}

// Every file read must be a regular file: opening a named pipe that no
// one writes would block the grader forever.
bool present(const std::string& path, const std::string& name, const std::string& flag, std::string* failure) {
  std::error_code st_ec;
  const fs::file_status st = fs::symlink_status(path, st_ec);  // a link is not the render's file
  if (!fs::exists(st)) *failure = "wrote no " + name + " (" + flag + ")";
  else if (!fs::is_regular_file(st)) *failure = "the " + name + " (" + flag + ") is not a regular file";
  return fs::is_regular_file(st);
}

// The course's PNG must be there and be a real PNG of the right size.
bool check_png(const std::string& abs_dir, int w, int h, std::string* failure) {
  if (!present(abs_dir + "/render.png", "image", "-f render.png", failure)) return false;
  try {
    const ImageBuffer png = read_png_image(abs_dir + "/render.png");
    return size_matches(png, w, h, "the PNG image", failure);
  } catch (const std::exception& e) {
    *failure = std::string("unreadable PNG: ") + e.what();
    return false;
  }
}

// The float image is what gets scored.
bool read_radiance(const std::string& abs_dir, int w, int h, ImageBuffer* radiance, std::string* failure) {
  if (!present(abs_dir + "/render.pfm", "floating-point image", "--pfm render.pfm", failure)) return false;
  try {
    *radiance = pt::read_pfm(abs_dir + "/render.pfm");
  } catch (const std::exception& e) {
    *failure = std::string("unreadable PFM: ") + e.what();
    return false;
  }
  return size_matches(*radiance, w, h, "the PFM image", failure);
}

bool all_finite(const ImageBuffer& radiance, std::string* failure) {
  int fx = 0, fy = 0;
  const int bad = count_non_finite(radiance, &fx, &fy);
  if (!bad) return true;
  char buf[160];
  std::snprintf(buf, sizeof buf, "%d pixel%s NaN or infinite (the first at x=%d, y=%d from the top)", bad,
                bad == 1 ? " is" : "s are", fx, fy);
  *failure = buf;
  return false;
}

// Radiance is never negative; a negative pixel means a negative
// contribution was added (a light sample below the surface, say).
// Float round-off of a correct sum can dip just below zero (-1e-7 on
// values near 1), so only values below -kNegativeTolerance count.
bool none_negative(const ImageBuffer& radiance, std::string* failure) {
  constexpr float kNegativeTolerance = 1e-4f;
  int negative = 0, nx = 0, ny = 0;
  for (int y = 0; y < radiance.height; ++y)
    for (int x = 0; x < radiance.width; ++x)
      for (int ch = 0; ch < 3; ++ch)
        if (value_from_top(radiance, x, y, ch) < -kNegativeTolerance) {
          if (negative++ == 0) nx = x, ny = y;
          break;
        }
  if (negative == 0) return true;
  char buf[160];
  std::snprintf(buf, sizeof buf, "%d pixel%s negative radiance below -1e-4 (the first at x=%d, y=%d from the top)", negative,
                negative == 1 ? " has" : "s have", nx, ny);
  *failure = buf;
  return false;
}

bool read_rate(const std::string& abs_dir, int w, int h, ImageBuffer* rate, std::string* failure) {
  const std::string rate_path = abs_dir + "/render_rate.png";
  if (!present(rate_path, "sample-rate image", "render_rate.png", failure)) return false;
  try {
    *rate = rate_from_colors(read_png_image(rate_path));
  } catch (const std::exception& e) {
    *failure = std::string("unreadable rate PNG: ") + e.what();
    return false;
  }
  return size_matches(*rate, w, h, "the rate image", failure);
}

// Only cost cases need the statistics, and they say so when it is missing.
void read_stats(const std::string& abs_dir, RenderOutput* out) {
  std::error_code ec;
  if (!fs::is_regular_file(abs_dir + "/stats.json", ec)) return;
  try {
    out->stats = pt::read_json_file(abs_dir + "/stats.json");
    out->has_stats = out->stats.type == Json::Type::Object;
  } catch (const std::exception&) {
    out->has_stats = false;
  }
}

// Checks the files of a render that exited normally in `abs_dir` and reads
// them into `out`: the folder's size, the PNG, the PFM (finite, not
// negative), the rate PNG when `want_rate`, and the statistics when there
// are any. False with out->failure set at the first problem.
bool read_outputs(const RunSettings& s, const Case& c, const std::string& abs_dir, bool want_rate, RenderOutput* out) {
  if (!output_within_limit(s, abs_dir, &out->failure)) return false;
  int w = 0, h = 0;
  case_resolution(c, &w, &h);
  if (!check_png(abs_dir, w, h, &out->failure)) return false;
  if (!read_radiance(abs_dir, w, h, &out->radiance, &out->failure)) return false;
  if (!all_finite(out->radiance, &out->failure) || !none_negative(out->radiance, &out->failure)) return false;
  if (want_rate && !read_rate(abs_dir, w, h, &out->rate, &out->failure)) return false;
  read_stats(abs_dir, out);
  return true;
}

}  // namespace

std::vector<std::string> case_input_files(const RunSettings& s, const Case& c) {
  std::vector<std::string> files = {fs::absolute(fs::path(s.scenes_dir) / c.scene).string()};
  for (size_t i = 1; i < c.options.size(); ++i) {
    if (c.options[i - 1] != "-e" && c.options[i - 1] != "-c") continue;
    const fs::path value(c.options[i]);
    std::error_code ec;
    if (value.is_absolute()) files.push_back(value.string());
    else if (!c.files_dir.empty() && fs::exists(fs::path(c.files_dir) / value, ec))
      files.push_back(fs::absolute(fs::path(c.files_dir) / value).string());
    else files.push_back(fs::absolute(fs::path(s.scenes_dir) / value).string());
  }
  return files;
}

RenderOutput render_case(const RunSettings& s, const Case& c, int part, uint64_t seed, const std::string& dir,
                         bool want_rate) {
  RenderOutput out;
  std::error_code ec;
  fs::remove_all(dir, ec);
  fs::create_directories(dir, ec);
  if (ec) {
    out.failure = "cannot create " + dir + ": " + ec.message();
    return out;
  }
  const std::string abs_dir = fs::absolute(dir).string();
  const std::string binary = fs::absolute(s.pathtracer).string();
  Staging staging;
  const Account* account = s.sandbox.account();
  const std::vector<std::string> inputs = case_input_files(s, c);
  std::vector<std::string> argv;
  if (s.sandbox.on()) {
    std::vector<std::string> staged = inputs;
    staged.push_back(binary);
    std::string why;
    if (!staging.stage(s.sandbox, account, staged, &why)) {
      out.failure = "grader error: " + why;
      return out;
    }
    const auto inside = [&](const std::string& f) { return staging.input_path(f); };
    argv = staging.command(render_argv(s, c, part, seed, inputs, inside(binary), staging.out_path(), inside));
  } else {
    argv = render_argv(s, c, part, seed, inputs, binary, abs_dir, [](const std::string& f) { return f; });
  }
  Limits limits;
  limits.wall_seconds = c.timeout_seconds * s.timeout_scale;
  limits.cpu_seconds = limits.wall_seconds * (s.threads + 1);
  limits.memory_bytes = s.memory_bytes;
  limits.file_bytes = s.output_bytes;
  limits.stop_on_stderr = [part](const std::string& line) { return todo_dooms(todo_part(line), part); };
  if (account) limits.run_uid = int(account->uid), limits.run_gid = int(account->gid);
  limits.clear_environment = s.sandbox.on();
  limits.no_network = s.sandbox.mode == SandboxMode::User;  // bwrap's has no network at all
  out.child = run_child(argv, s.sandbox.on() ? staging.workdir() : abs_dir, abs_dir + "/stdout.txt",
                        abs_dir + "/stderr.txt", limits);
  if (account) kill_account_processes(*account);  // whatever it left running
  std::vector<std::string> refused;
  bool too_much = false;
  if (s.sandbox.on()) {
    too_much = directory_bytes(staging.workdir()) > s.output_bytes;
    if (!too_much) staging.collect(kRenderFiles, abs_dir, s.output_bytes, &refused);
  }
  out.seconds = out.child.seconds;
  out.log = log_excerpt(abs_dir);
  out.todo = todo_lines(abs_dir + "/stderr.txt");
  out.stopped_at_todo = out.child.stopped;

  if (!out.child.started || out.child.timed_out || out.child.signal != 0 || out.child.exit_code != 0) {
    out.failure = describe(out.child, limits);
    return out;
  }
  if (too_much) {
    out.failure = "wrote more than the " + std::to_string(s.output_bytes >> 20) + " MB limit into its folder: not read";
    return out;
  }
  if (!refused.empty()) {
    out.failure = "wrote " + refused[0] + " as something else than a file of its own (a link, a folder, a file linked "
                  "elsewhere or too large): not read";
    return out;
  }
  out.ok = read_outputs(s, c, abs_dir, want_rate, &out);
  return out;
}

}  // namespace grader
