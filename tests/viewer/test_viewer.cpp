// The viewer's C++ parts without a browser: the camera file it writes, the
// files it lets the page open, the progressive render's schedule, and
// Debug mode's reading of the page's input.
#include <catch2/catch.hpp>

#include <unistd.h>

#include <algorithm>
#include <cstring>

#include <filesystem>
#include <fstream>
#include <string>

#include "viewer/access.h"
#include "viewer/camera_file.h"
#include "common/collada.h"
#include "common/image_io.h"
#include "viewer/debug_api.h"
#include "viewer/debugger/debugger.h"
#include "common/json.h"
#include "common/todo.h"
#include "viewer/file_access.h"
#include "viewer/overlays.h"
#include "pathtracer/render_job.h"
#include "viewer/progressive.h"

namespace fs = std::filesystem;
using namespace pt;

namespace {

// A fresh temporary folder, removed at the end of the test.
struct TempDir {
  fs::path path;
  TempDir() {
    char tmpl[] = "/tmp/pt-viewer-test-XXXXXX";
    path = ::mkdtemp(tmpl);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

void touch(const fs::path& p) { std::ofstream(p) << "x"; }

}  // namespace

TEST_CASE("the saved camera file gives back the viewer's camera exactly through -c", "[viewer]") {
  Scene scene = load_collada(std::string(PT_PROJECT_SCENES_DIR) + "/CBspheres_lambertian.dae");
  RenderOptions opts;
  opts.width = 480;
  opts.height = 360;
  opts.lens_radius = 0.03;
  opts.lens_radius_set = true;
  Camera cam = scene.camera;
  configure_camera(cam, opts);
  cam.look_at(Vec3d(0.7, 1.1, 3.3), Vec3d(0.1, 0.5, -0.2), Vec3d(0, 1, 0));

  TempDir dir;
  const std::string file = (dir.path / "camera.txt").string();
  std::ofstream(file) << viewer::camera_settings_text(cam);
  RenderOptions with_file = opts;
  with_file.camera_settings = file;
  Camera back = scene.camera;
  configure_camera(back, with_file);  // what pathtracer -c does

  CHECK(back.position.x == cam.position.x);
  CHECK(back.position.y == cam.position.y);
  CHECK(back.position.z == cam.position.z);
  for (const auto& [a, b] : {std::pair{back.axis_x, cam.axis_x}, {back.axis_y, cam.axis_y}, {back.axis_z, cam.axis_z}}) {
    CHECK(a.x == b.x);
    CHECK(a.y == b.y);
    CHECK(a.z == b.z);
  }
  CHECK(back.hfov_deg == cam.hfov_deg);
  CHECK(back.vfov_deg == cam.vfov_deg);
  CHECK(back.screen_dist == cam.screen_dist);
  CHECK(back.near_clip == cam.near_clip);
  CHECK(back.far_clip == cam.far_clip);
  CHECK(back.lens_radius == cam.lens_radius);
  CHECK(back.focal_distance == cam.focal_distance);
  CHECK(back.width == 480);
  CHECK(back.height == 360);
}

TEST_CASE("the page opens only files of the right kind inside the allowed folders", "[viewer]") {
  TempDir allowed, outside;
  fs::create_directories(allowed.path / "sub");
  touch(allowed.path / "scene.dae");
  touch(allowed.path / "sub" / "deep.dae");
  touch(allowed.path / "camera.txt");
  touch(allowed.path / "notes.md");
  touch(outside.path / "secret.dae");
  fs::create_symlink(outside.path / "secret.dae", allowed.path / "link.dae");
  fs::create_symlink(outside.path, allowed.path / "door");
  fs::create_symlink(allowed.path / "scene.dae", allowed.path / "alias.dae");

  viewer::FileAccess files;
  files.allow_folder(allowed.path.string());
  std::string why;
  const auto scene = [&](const fs::path& p) { return files.resolve(p.string(), viewer::FileKind::Scene, &why); };
  const std::string root = fs::canonical(allowed.path).string();

  CHECK(scene(allowed.path / "scene.dae") == root + "/scene.dae");
  CHECK(scene(allowed.path / "sub" / ".." / "scene.dae") == root + "/scene.dae");
  CHECK(scene(allowed.path / "sub" / "deep.dae") == root + "/sub/deep.dae");
  CHECK(scene(allowed.path / "alias.dae") == root + "/scene.dae");  // a link that stays inside
  CHECK(scene(allowed.path / "link.dae").empty());                  // a link out
  CHECK(why.find("not a file the viewer may open") != std::string::npos);
  CHECK(scene(allowed.path / "door" / "secret.dae").empty());       // through a linked folder
  CHECK(scene(allowed.path / ".." / outside.path.filename() / "secret.dae").empty());
  CHECK(scene(outside.path / "secret.dae").empty());
  CHECK(scene("/etc/passwd").empty());
  CHECK(scene(allowed.path / "missing.dae").empty());
  CHECK(scene(allowed.path / "notes.md").empty());                  // not a scene
  CHECK(scene(allowed.path / "sub").empty());                       // a folder
  CHECK(scene("").empty());

  const auto listed = files.list(viewer::FileKind::Scene);
  CHECK(listed == std::vector<std::string>{root + "/scene.dae", root + "/sub/deep.dae"});
  CHECK_THROWS(files.allow_folder((allowed.path / "scene.dae").string()));
}

TEST_CASE("the progressive render's passes take 1, 2, 4, ... samples and end at -s, as far as samples can be kept",
          "[viewer]") {
  using V = std::vector<int>;
  const long long all = 1LL << 40;
  CHECK(viewer::pass_schedule(1, all) == V{1});
  CHECK(viewer::pass_schedule(16, all) == V{1, 2, 4, 8, 16});
  CHECK(viewer::pass_schedule(5, all) == V{1, 2, 4, 5});
  CHECK(viewer::pass_schedule(64, 10) == V{1, 2, 4, 8, 64});
  CHECK(viewer::pass_schedule(64, 1) == V{1, 64});
  CHECK(viewer::pass_schedule(1 << 20, all).size() == 21);
  // 16 bytes a kept sample: 480x360 keeps 194 a pixel, 8192x4096 one (not two).
  CHECK(viewer::samples_kept(480 * 360) == 194);
  CHECK(viewer::samples_kept(8192LL * 4096) == 1);
  CHECK(viewer::pass_schedule(64, viewer::samples_kept(8192LL * 4096)) == V{1, 64});
}

// Whether this build's pixel functions are written (in the starter kit
// they are stubs that take one sample whatever -s, so that no pass has
// samples to reuse).
bool pixel_functions_written() {
  for (const TodoSite& s : todo_sites())
    if (s.part == 1 || s.part == 5) return false;
  return true;
}

// Every pass of the viewer's progressive render against the command line's
// render_scene at that pass's sample count: bit for bit, and (pixel
// functions written) every sample of a pass but the new ones taken from
// the pass before.
void check_passes(const std::string& scene_name, RenderOptions o, const std::string& what) {
  const bool counted = pixel_functions_written();
  if (!counted) WARN("parts 1 and 5's pixel functions are stubs here: only the images are compared");
  Scene scene = load_collada(std::string(PT_PROJECT_SCENES_DIR) + "/" + scene_name);
  configure_camera(scene.camera, o);
  const long long pixels = o.cell_set ? (long long)o.cell_w * o.cell_h : (long long)o.width * o.height;
  std::vector<int> counts;
  long long before = 0, total_traced = 0;
  viewer::PassHooks hooks;
  hooks.pass_done = [&](int pass, const RenderOptions& po, const RenderResult& r, uint64_t traced, uint64_t reused) {
    INFO(what << ": pass " << pass << " at " << po.samples_per_pixel << " samples");
    counts.push_back(po.samples_per_pixel);
    RenderOptions cli = o;
    cli.samples_per_pixel = po.samples_per_pixel;
    const RenderResult expected = render_scene(scene, cli);
    CHECK(std::memcmp(r.image.pixels.data(), expected.image.pixels.data(), r.image.pixels.size() * sizeof(Color)) == 0);
    CHECK(r.image.samples == expected.image.samples);
    long long taken = 0;
    for (uint32_t n : r.image.samples) taken += n;
    // Reused: every sample the pass before took (pass 1's centre rays are
    // not jittered: none); traced: the rest.
    if (counted) {
      CHECK((long long)reused == (pass <= 1 ? 0 : before));
      CHECK((long long)(traced + reused) == taken);
    }
    before = taken;
    total_traced += (long long)traced;
  };
  viewer::render_progressive(scene, o, hooks);
  CHECK(counts == viewer::pass_schedule(o.samples_per_pixel, viewer::samples_kept(pixels)));
  // All passes together trace the last pass's samples and pass 1's.
  if (counted) CHECK(total_traced == before + pixels);
}

TEST_CASE("the progressive render's passes are the command line's images bit for bit, each reusing the one before",
          "[viewer]") {
  RenderOptions o;
  o.width = 40;
  o.height = 30;
  o.threads = 2;
  o.seed = 7;
  o.progress = false;
  o.scene_path = "CBspheres_lambertian.dae";
  o.part = 4;
  o.samples_per_pixel = 16;
  o.light_samples = 2;
  o.max_depth = 4;
  check_passes("CBspheres_lambertian.dae", o, "part 4");
  o.samples_per_pixel = 12;  // the last pass is not a power of two
  check_passes("CBspheres_lambertian.dae", o, "part 4, -s 12");
  o.part = 5;  // adaptive: pixels stop at a batch's end, in the last pass too
  o.samples_per_pixel = 64;
  o.adaptive_batch = 8;
  o.adaptive_tolerance = 0.1;
  check_passes("CBspheres_lambertian.dae", o, "part 5");
  o.part = 3;
  o.samples_per_pixel = 8;
  o.cell_set = true;  // a cell: only its pixels
  o.cell_x = 5;
  o.cell_y = 7;
  o.cell_w = 11;
  o.cell_h = 9;
  check_passes("CBspheres_lambertian.dae", o, "part 3, a cell");
}

TEST_CASE("Debug mode reads the page's input, refuses absurd values, and answers with the debugger's result", "[viewer]") {
  RenderOptions o;
  o.width = 32;
  o.height = 24;
  o.samples_per_pixel = 2;
  o.scene_path = std::string(PT_PROJECT_SCENES_DIR) + "/CBspheres_lambertian.dae";
  int loads = 0;
  const auto load = [&] {
    ++loads;
    Scene s = load_collada(o.scene_path);
    configure_camera(s.camera, o);
    return s;
  };
  const std::string tri = R"("triangle":{"p1":[-1,-1,-2],"p2":[1,-1,-2],"p3":[0,1,-2]})";
  const Json hit = parse_json(
      viewer::run_debug_tool("intersect", R"({"ray":{"origin":[0,0,0],"direction":[0,0,-1]},)" + tri + "}", o, load), "t");
  CHECK(hit.flag("hit"));
  CHECK(hit.num("t") == 2.0);
  CHECK(loads == 0);  // a typed shape needs no scene
  // "nan" and "inf" reach the tool's own checks; other text is refused here.
  using debug::InputError;
  CHECK_THROWS_AS(viewer::run_debug_tool("intersect", R"({"ray":{"origin":[0,0,0],"direction":[0,"nan",-1]},)" + tri + "}", o, load),
                  InputError);
  CHECK_THROWS_AS(viewer::run_debug_tool("intersect", R"({"ray":{"origin":[0,0,0],"direction":[0,"x",-1]},)" + tri + "}", o, load),
                  InputError);
  CHECK_THROWS_AS(viewer::run_debug_tool("intersect", R"({"ray":{"origin":[0,0,0],"direction":[0,0,-1],"min_t":3,"max_t":1},)" + tri + "}",
                                         o, load),
                  InputError);
  CHECK_THROWS_AS(viewer::run_debug_tool("intersect", R"({"ray":{"origin":[0,0,0],"direction":[0,0,-1]},"sphere":{"center":[0,0,-3],"radius":-1}})",
                                         o, load),
                  InputError);
  CHECK_THROWS_AS(viewer::run_debug_tool("intersect", R"({"ray":{"origin":[0,0,0],"direction":[0,0,-1]}})", o, load), InputError);
  CHECK_THROWS_AS(viewer::run_debug_tool("intersect", "[1, 2]", o, load), InputError);
  CHECK_THROWS_AS(viewer::run_debug_tool("teleport", "{}", o, load), InputError);
  // Pixels and samples out of range, and a light beyond the scene's.
  CHECK_THROWS_AS(viewer::run_debug_tool("path", R"({"x":32,"y":0,"sample":0})", o, load), InputError);
  CHECK_THROWS_AS(viewer::run_debug_tool("path", R"({"x":0,"y":-1,"sample":0})", o, load), InputError);
  CHECK_THROWS_AS(viewer::run_debug_tool("path", R"({"x":0,"y":0,"sample":2})", o, load), InputError);
  CHECK_THROWS_AS(viewer::run_debug_tool("path", R"({"x":0.5,"y":0,"sample":0})", o, load), InputError);
  CHECK_THROWS_AS(
      viewer::run_debug_tool("lights", R"({"light":1,"point":[0,0,0],"normal":[0,1,0],"samples":4,"seed":1})", o, load),
      InputError);
  CHECK_THROWS_AS(
      viewer::run_debug_tool("lights", R"({"light":0,"point":[0,0,0],"normal":[0,1,0],"samples":0,"seed":1})", o, load),
      InputError);
  // A pixel's sample: the record of the path, starting at the camera.
  const Json path = parse_json(viewer::run_debug_tool("path", R"({"x":16,"y":12,"sample":1})", o, load), "path");
  CHECK(path.num("sample") == 1);
  CHECK(path.get("steps") != nullptr);
  const Json* pixel = path.get("pixel");
  REQUIRE(pixel);
  CHECK(pixel->array.at(0).number == 16);
  CHECK(pixel->array.at(1).number == 12);
  // The light-sample tester with the light's shape for drawing.
  const Json lights = parse_json(
      viewer::run_debug_tool("lights", R"({"light":0,"point":[0,0.01,0],"normal":[0,1,0],"samples":5,"seed":1})", o, load), "l");
  CHECK(lights.get("samples")->array.size() == 5);
  CHECK(lights.get("light_shape")->str("type") == "area");
}

TEST_CASE("requests another site's page can make a browser send are refused, the page's own are not", "[viewer]") {
  const std::string token(32, 'a');
  const int port = 8123;
  // The viewer's own page: its Host, Origin and cookie, JSON.
  const auto page = [&](const std::string& method, const std::string& path) {
    httplib::Request r;
    r.method = method;
    r.path = path;
    r.headers.emplace("Host", "127.0.0.1:8123");
    r.headers.emplace("Cookie", "other=1; pt_viewer_8123=" + token);
    r.headers.emplace("Sec-Fetch-Site", "same-origin");
    if (method == "POST") {
      r.headers.emplace("Origin", "http://127.0.0.1:8123");
      r.headers.emplace("Content-Type", "application/json");
    }
    return r;
  };
  const auto status = [&](const httplib::Request& r) { return viewer::check_request(r, token, port).status; };
  const auto with = [](httplib::Request r, const std::string& key, const std::string& value) {
    r.headers.erase(key);
    r.headers.emplace(key, value);
    return r;
  };
  CHECK(status(page("GET", "/api/state")) == 0);
  CHECK(status(page("POST", "/api/render")) == 0);
  CHECK(status(with(page("POST", "/api/render"), "Content-Type", "application/json; charset=utf-8")) == 0);
  CHECK(status(with(page("GET", "/api/state"), "Host", "localhost:8123")) == 0);
  CHECK(viewer::cookie_name(port) == "pt_viewer_8123");

  // Another port of the same host: same-site, another Origin.
  CHECK(status(with(page("POST", "/api/render"), "Origin", "http://127.0.0.1:9000")) == 403);
  CHECK(status(with(page("POST", "/api/render"), "Origin", "null")) == 403);
  CHECK(status(with(page("POST", "/api/render"), "Sec-Fetch-Site", "same-site")) == 403);
  CHECK(status(with(page("GET", "/api/image"), "Sec-Fetch-Site", "cross-site")) == 403);
  // Bodies another page can send without asking: text and forms.
  CHECK(status(with(page("POST", "/api/render"), "Content-Type", "text/plain;charset=UTF-8")) == 415);
  CHECK(status(with(page("POST", "/api/render"), "Content-Type", "application/x-www-form-urlencoded")) == 415);
  CHECK(status(with(page("POST", "/api/render"), "Content-Type", "multipart/form-data; boundary=x")) == 415);
  httplib::Request no_type = page("POST", "/api/stop");
  no_type.headers.erase("Content-Type");
  CHECK(status(no_type) == 415);
  // DNS rebinding: a name of another site pointed at 127.0.0.1.
  CHECK(status(with(page("GET", "/api/state"), "Host", "evil.example:8123")) == 403);
  CHECK(status(with(page("GET", "/api/state"), "Host", "127.0.0.1:9000")) == 403);
  httplib::Request no_host = page("GET", "/api/state");
  no_host.headers.erase("Host");
  CHECK(status(no_host) == 403);
  // The token: another viewer's cookie, the old shared name, or none.
  CHECK(status(with(page("GET", "/api/state"), "Cookie", "pt_viewer_9000=" + token)) == 403);
  CHECK(status(with(page("GET", "/api/state"), "Cookie", "pt_viewer_token=" + token)) == 403);
  CHECK(status(with(page("GET", "/api/state"), "Cookie", "pt_viewer_8123=" + std::string(32, 'b'))) == 403);
  const viewer::Refusal no_token = viewer::check_request(with(page("GET", "/"), "Cookie", ""), token, port);
  CHECK(no_token.status == 403);
  CHECK(no_token.reason.find("open the URL the viewer printed") != std::string::npos);
  // A program with the token (curl): no Origin, no Sec-Fetch-Site.
  httplib::Request curl;
  curl.method = "POST";
  curl.path = "/api/render";
  curl.headers.emplace("Host", "127.0.0.1:8123");
  curl.headers.emplace("X-Token", token);
  curl.headers.emplace("Content-Type", "application/json");
  CHECK(status(curl) == 0);
  // The printed URL opened from anywhere (a terminal, another page): the
  // page, with the token in the URL; the cookie alone does not do.
  httplib::Request opened = with(with(page("GET", "/"), "Sec-Fetch-Site", "cross-site"), "Cookie", "");
  opened.params.emplace("token", token);
  CHECK(status(opened) == 0);
  CHECK(status(with(page("GET", "/"), "Sec-Fetch-Site", "same-site")) == 403);
  httplib::Request api_from_elsewhere = with(page("GET", "/api/state"), "Sec-Fetch-Site", "cross-site");
  api_from_elsewhere.params.emplace("token", token);
  CHECK(status(api_from_elsewhere) == 403);
}

TEST_CASE("camera files are files of the course's format; nothing of another file is quoted", "[viewer]") {
  TempDir allowed, outside;
  const std::string six = "30 22.5 1.333 0.1 100\n0 1 4 0 1 0\n1.57 0 4 0.4 40\n1 0 0 0 1 0 0 0 1\n480 360 1\n4 0\n";
  std::ofstream(allowed.path / "camera.txt") << six;
  std::ofstream(allowed.path / "view") << "\n" << six << "\n";  // no extension, blank lines around
  std::ofstream(allowed.path / "notes") << "SECRET_WORD=swordfish\n";
  std::ofstream(allowed.path / "short.txt") << "30 22.5 1.333 0.1 100\n0 1 4 0 1 0\n";
  std::ofstream(allowed.path / "words.txt") << "30 22.5 1.333 0.1 100\n0 1 4 0 1 zero\n1.57 0 4 0.4 40\n";
  std::ofstream(allowed.path / "huge.txt") << six << std::string(20000, ' ') << "\n";
  std::ofstream(outside.path / "secret.txt") << six;
  viewer::FileAccess files;
  files.allow_folder(allowed.path.string());
  const std::string root = fs::canonical(allowed.path).string();
  std::string why;
  const auto camera = [&](const fs::path& p) { return files.resolve(p.string(), viewer::FileKind::Camera, &why); };
  CHECK(camera(allowed.path / "camera.txt") == root + "/camera.txt");
  CHECK(camera(allowed.path / "view") == root + "/view");
  for (const char* name : {"notes", "short.txt", "words.txt", "huge.txt"}) {
    INFO(name);
    CHECK(camera(allowed.path / name).empty());
    CHECK(why.find("not a camera settings file") != std::string::npos);
    CHECK(why.find("SECRET") == std::string::npos);
    CHECK(why.find("zero") == std::string::npos);
  }
  CHECK(files.list(viewer::FileKind::Camera) == std::vector<std::string>{root + "/camera.txt", root + "/view"});

  // With everything allowed, a file of the system is still no camera file.
  viewer::FileAccess everything;
  everything.allow_folder("/");
  CHECK(everything.resolve("/proc/self/environ", viewer::FileKind::Camera, &why).empty());
  CHECK(why == "/proc/self/environ: not a camera settings file (the course's six lines of numbers)");

  // Outside the folders, a file that is there and one that is not get the
  // same answer; inside, a missing file is said to be missing.
  std::string there, missing;
  CHECK(camera(outside.path / "secret.txt").empty());
  there = why.substr(why.find(':'));
  CHECK(camera(outside.path / "nothing.txt").empty());
  missing = why.substr(why.find(':'));
  CHECK(there == missing);
  CHECK(camera(allowed.path / ".." / outside.path.filename() / "nothing.txt").empty());
  CHECK(why.substr(why.find(':')) == missing);
  CHECK(camera(allowed.path / "nothing.txt").empty());
  CHECK(why == (allowed.path / "nothing.txt").string() + ": no such file");
}

TEST_CASE("an earlier pass of a case's render is not compared yet: the difference comes at its sample count", "[viewer]") {
  viewer::ViewerCase vc;
  vc.c.name = "p3_spheres_light";
  vc.opts.part = 3;
  vc.opts.samples_per_pixel = 16;
  vc.opts.light_samples = 4;
  vc.opts.width = 128;
  vc.opts.height = 96;
  vc.opts.scene_path = "/scenes/CBspheres_lambertian.dae";
  RenderOptions render = vc.opts;
  render.threads = 2;
  render.seed = 9;  // threads and seed do not make another image
  viewer::Frame f;
  f.width = 128;
  f.height = 96;
  f.samples = 4;
  CHECK(viewer::difference_pending(f, render, vc) == "difference shown when the render reaches 16 samples (now 4)");
  f.samples = 16;
  CHECK(viewer::difference_pending(f, render, vc).empty());  // the last pass: compared
  f.samples = 4;
  RenderOptions other = render;
  other.light_samples = 8;
  CHECK(viewer::difference_pending(f, other, vc).empty());  // not the case's render: refused as before
  other = render;
  other.samples_per_pixel = 4;
  CHECK(viewer::difference_pending(f, other, vc).empty());
  other = render;
  other.cell_set = true;
  CHECK(viewer::difference_pending(f, other, vc).empty());
}

namespace {

// A frame holding `img` as the worker sends it (20 bytes a pixel).
viewer::Frame frame_of(const ImageBuffer& img, int samples) {
  viewer::Frame f;
  f.kind = "render";
  f.width = img.width;
  f.height = img.height;
  f.samples = samples;
  f.payload.resize(img.pixels.size() * 20, 0);
  for (size_t i = 0; i < img.pixels.size(); ++i) {
    const uint32_t n = uint32_t(samples);
    std::memcpy(&f.payload[i * 20], &img.pixels[i], 12);
    std::memcpy(&f.payload[i * 20 + 12], &n, 4);
  }
  return f;
}

}  // namespace

TEST_CASE("the difference overlay names the likely causes of a render that differs, none of one that matches",
          "[viewer]") {
  // The project's own case, reference and catalogue: p3_spheres_light's
  // reference mean times pi is what a diffuse BSDF that leaves out the
  // division by pi renders (grader/known_bugs.json: albedo_not_over_pi).
  const fs::path root = fs::path(PT_PROJECT_SCENES_DIR).parent_path();
  viewer::FileAccess files;
  files.allow_folder((root / "scenes").string());
  const std::vector<viewer::ViewerCase> cases = viewer::load_cases(root.string(), files);
  const viewer::ViewerCase* vc = viewer::find_case(cases, "p3_spheres_light");
  REQUIRE(vc);
  const grader::Catalogue catalogue = viewer::load_catalogue(root.string());
  REQUIRE(!catalogue.bugs.empty());
  std::vector<grader::Case> all;
  for (const viewer::ViewerCase& c : cases) all.push_back(c.c);
  const grader::CaseGroups groups = grader::case_groups(all);
  const std::string refs = (root / "reference_images").string();
  const ImageBuffer mean = read_pfm(refs + "/p3_spheres_light/mean.pfm");
  ImageBuffer times_pi = mean;
  for (Color& c : times_pi.pixels) c = c * 3.14159265f;

  const auto compare = [&](const ImageBuffer& img, const grader::Catalogue& cat) {
    return viewer::difference_overlay(frame_of(img, 16), vc->opts, *vc, refs, cat, groups);
  };
  const viewer::Difference bright = compare(times_pi, catalogue);
  CHECK_THAT(bright.verdict, Catch::StartsWith("differs from the reference"));
  const Json j = parse_json(viewer::hints_json(bright), "X-Hints");
  const Json* hints = j.get("hints");
  REQUIRE(hints);
  REQUIRE(hints->type == Json::Type::Array);
  REQUIRE(!hints->array.empty());
  CHECK(hints->array.size() <= 3);
  const Json& first = hints->array[0];
  const auto pi_bug = std::find_if(catalogue.bugs.begin(), catalogue.bugs.end(),
                                   [](const grader::KnownBug& b) { return b.name == "albedo_not_over_pi"; });
  REQUIRE(pi_bug != catalogue.bugs.end());
  CHECK(first.str("function") == pi_bug->function);
  CHECK(first.str("file") == "common/bsdf.h");
  CHECK(first.str("readme") == "stages/part3_direct_lighting/README.md");
  CHECK(first.str("section") == "Given code");
  CHECK(first.str("text") == "every lit image is too bright by about pi (image x3.1): is the diffuse BSDF the albedo "
                             "divided by pi?");
  for (const Json& h : hints->array) CHECK(h.str("section").find('`') == std::string::npos);  // words, not Markdown
  CHECK(j.get("note") == nullptr);

  const viewer::Difference same = compare(mean, catalogue);
  CHECK_THAT(same.verdict, Catch::StartsWith("matches the reference"));
  CHECK(viewer::hints_json(same) == "{\"hints\":[]}");

  // A catalogue whose one bug fails another case: nothing in it is close.
  grader::Catalogue other;
  other.bugs.push_back(catalogue.bugs[0]);
  other.bugs[0].cases = {{"p1_spheres", grader::CaseSignature{true, {{"mean_ratio", 0.9}}}}};
  const Json none = parse_json(viewer::hints_json(compare(times_pi, other)), "X-Hints");
  CHECK(none.get("hints")->array.empty());
  CHECK(none.str("note") == grader::kNoHintClose);
  // No catalogue: no causes, and no note either.
  CHECK(viewer::hints_json(compare(times_pi, grader::Catalogue{})) == "{\"hints\":[]}");
}
