// A hostile stand-in for a student's pathtracer, for the grader's robustness
// tests. It takes the command line the grader gives any pathtracer
//   --part N [case options] -t T --seed S --no-progress
//   -f PNG --pfm PFM --stats-json JSON SCENE
// reads -r W H, -f, --pfm and --stats-json (everything else is ignored; the
// scene is the last argument) and misbehaves as the environment says:
//
//   FAKE_STUDENT_MODE  what to do (below). "by_scene": the scene file's name
//                      without its extension, so that one case list can
//                      hold a case per mode.
//   FAKE_STUDENT_MEAN  a PFM (a reference's mean.pfm) written as the image
//                      by the modes that write valid files; a constant grey
//                      when unset.
//   FAKE_STUDENT_PIDS  a file to which every process that must not outlive
//                      the grader appends "<pid> <start time>" (the start
//                      time from /proc/<pid>/stat tells a reused pid apart).
//
// Modes:
//   good            valid PNG, PFM and stats JSON of the right size
//   crash           raise(SIGSEGV)
//   hang            forks a child; both wait forever (pause)
//   fork_hang       forks children (one with a grandchild) that ignore
//                   SIGTERM and SIGHUP and wait forever, writes valid files,
//                   exits 0
//   garbage         binary bytes, invalid UTF-8, terminal escapes, HTML and
//                   JSON metacharacters on stdout and stderr; writes nothing
//   truncated_png   the first half of a valid PNG, valid PFM and stats
//   nan             valid files, but the PFM has a NaN pixel at x=3, y=2
//                   and an infinite one at x=10, y=9 (from the top)
//   wrong_size      valid files of half the width and height
//   wrong_size_pfm  the PNG of the right size, the PFM of half the size
//   nothing         exits 0, writes nothing
//   no_pfm          the PNG and the stats, no PFM
//   disk_fill       one ever-growing file (the grader's RLIMIT_FSIZE kills
//                   it); gives up at 32 MB and exits 0 with valid files, so
//                   a missing limit shows as a wrong message, not a full disk
//   disk_fill_many  four files of 0.75 MB (each under a 1 MB per-file limit,
//                   3 MB in all), then valid files, exit 0
//   fifo            render.png is a named pipe nobody writes; valid PFM
//   fifo_stats      valid PNG and PFM; the stats JSON is a named pipe
//   huge_pfm        a valid PNG; the PFM's header claims 60000 x 60000
//                   pixels but 48 bytes of data follow
//   exit3           a message on stderr, exit status 3
//   todo_hang       prints a starter-kit stub's "TODO: implement Part 1: ..."
//                   line on stderr, then waits forever (the grader must stop
//                   it at that line, not at the timeout)
//   todo_part2      prints "TODO: implement Part 2: ..." (a stub BVH, slow
//                   but correct), then writes valid files
//   negative_roundoff  valid files with one channel at -1e-6 (round-off)
//   negative        valid files with one channel at -0.01
//   costly          valid files; the stats claim 100 tests per closest-hit query
//   costly_shadow   valid files; the stats claim one shadow query per pixel
//                   with 100 tests each
//   uncounted       valid files; the stats count no primitive test at all
//   probe_garbage, probe_link, probe_huge, probe_evil
//                   render as `nan` (a failed case, so that the grader runs
//                   the function checks); asked for the checks
//                   (`--probe FILE [--part N]`), write random bytes, a
//                   symbolic link to the references' probes.json, 20 MB
//                   (the grader's file-size limit for the checks is 8 MB),
//                   or valid JSON whose statuses, check names and
//                   tolerances are the fake's own words and numbers
// Asked for the checks in any other mode, it writes nothing and exits 0.
#include <fcntl.h>
#include <lodepng.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "common/image_io.h"

namespace {

struct Args {
  int width = 800, height = 600;
  std::string png, pfm, stats, scene;
};

Args parse(int argc, char** argv) {
  Args a;
  for (int i = 1; i < argc; ++i) {
    const std::string s = argv[i];
    if (s == "-r" && i + 2 < argc) {
      a.width = std::atoi(argv[i + 1]);
      a.height = std::atoi(argv[i + 2]);
      i += 2;
    } else if (s == "-f" && i + 1 < argc) {
      a.png = argv[++i];
    } else if (s == "--pfm" && i + 1 < argc) {
      a.pfm = argv[++i];
    } else if (s == "--stats-json" && i + 1 < argc) {
      a.stats = argv[++i];
    }
  }
  if (argc > 1) a.scene = argv[argc - 1];
  return a;
}

[[noreturn]] void die(const std::string& why) {
  std::fprintf(stderr, "fake_student: %s\n", why.c_str());
  std::exit(70);
}

std::string env(const char* name) {
  const char* v = std::getenv(name);
  return v ? v : "";
}

std::string mode_of(const Args& a) {
  std::string mode = env("FAKE_STUDENT_MODE");
  if (mode != "by_scene") return mode;
  std::string base = a.scene.substr(a.scene.find_last_of('/') + 1);
  return base.substr(0, base.find('.'));
}

// The image the valid-file modes write: the mean (when its size fits) or grey.
pt::ImageBuffer image(int w, int h) {
  const std::string mean = env("FAKE_STUDENT_MEAN");
  if (!mean.empty()) {
    pt::ImageBuffer img = pt::read_pfm(mean);
    if (img.width == w && img.height == h) return img;
  }
  pt::ImageBuffer img(w, h);
  for (auto& p : img.pixels) p = pt::Color(0.5f, 0.5f, 0.5f);
  return img;
}

std::vector<unsigned char> png_bytes(const pt::ImageBuffer& img) {
  const std::vector<uint8_t> rgb = pt::to_png_bytes(img);
  std::vector<unsigned char> png;
  if (lodepng::encode(png, std::vector<unsigned char>(rgb.begin(), rgb.end()), unsigned(img.width),
                      unsigned(img.height), LCT_RGB, 8) != 0)
    die("cannot encode a PNG");
  return png;
}

void write_bytes(const std::string& path, const void* data, size_t n) {
  FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) die("cannot write " + path);
  const bool ok = std::fwrite(data, 1, n, f) == n;
  if (std::fclose(f) != 0 || !ok) die("cannot write " + path);
}

// One closest-hit query per pixel with `tests` primitive tests each, and
// `shadow` shadow queries per pixel with `shadow_tests` tests each.
void write_stats(const Args& a, int w, int h, int tests = 2, int shadow = 0, int shadow_tests = 0) {
  if (a.stats.empty()) return;
  const long n = long(w) * h;
  std::ostringstream s;
  s << "{\n  \"width\": " << w << ",\n  \"height\": " << h << ",\n  \"render_seconds\": 0.001,\n"
    << "  \"rays\": " << n * (1 + shadow) << ",\n  \"closest_queries\": " << n << ",\n  \"shadow_queries\": "
    << n * shadow << ",\n  \"primitive_tests\": " << n * (tests + shadow * shadow_tests)
    << ",\n  \"shadow_primitive_tests\": " << n * shadow * shadow_tests
    << ",\n  \"mrays_per_second\": 1.0,\n  \"triangles\": 12\n}\n";
  const std::string text = s.str();
  write_bytes(a.stats, text.data(), text.size());
}

void write_image(const Args& a, const pt::ImageBuffer& img) {
  const std::vector<unsigned char> png = png_bytes(img);
  write_bytes(a.png, png.data(), png.size());
  pt::write_pfm(a.pfm, img);
}

void write_valid(const Args& a, int w, int h) {
  write_image(a, image(w, h));
  write_stats(a, w, h);
}

// Appends "<pid> <start time>" of this process to FAKE_STUDENT_PIDS.
void record_self() {
  const std::string path = env("FAKE_STUDENT_PIDS");
  if (path.empty()) return;
  std::ifstream in("/proc/self/stat");
  std::string stat((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  // Field 22 (start time); fields are counted after the ")" that ends field 2.
  std::istringstream rest(stat.substr(stat.rfind(')') + 2));
  std::string field;
  for (int i = 3; i <= 22 && (rest >> field); ++i) {
  }
  const std::string line = std::to_string(getpid()) + " " + field + "\n";
  const int fd = open(path.c_str(), O_WRONLY | O_APPEND | O_CREAT, 0644);
  if (fd < 0 || write(fd, line.data(), line.size()) != ssize_t(line.size())) _exit(71);
  close(fd);
}

[[noreturn]] void wait_forever() {
  for (;;) pause();
}

// Forks a child that records itself, says so through `ready`, optionally
// forks a grandchild that does the same, and waits forever.
void fork_waiter(int ready, bool with_grandchild) {
  const pid_t pid = fork();
  if (pid < 0) die("fork failed");
  if (pid > 0) return;
  signal(SIGTERM, SIG_IGN);
  signal(SIGHUP, SIG_IGN);
  if (with_grandchild) fork_waiter(ready, false);
  record_self();
  if (write(ready, "x", 1) != 1) _exit(72);
  wait_forever();
}

// Blocks until `n` processes have written their byte to the pipe.
void await(int ready_read, int n) {
  char c;
  for (int got = 0; got < n;)
    if (read(ready_read, &c, 1) == 1) ++got;
    else die("a child died before it was ready");
}

void garbage() {
  std::string head =
      "<script>alert('fake')</script> \"}], \\ \x1b[31mred\x1b[0m \xc3\x28 \xff\xfe \xed\xa0\x80 end\r\n";
  head.push_back('\0');
  std::mt19937 rng(184);
  for (FILE* f : {stdout, stderr}) {
    std::fwrite(head.data(), 1, head.size(), f);
    std::vector<unsigned char> noise(256 * 1024);
    for (auto& b : noise) b = static_cast<unsigned char>(rng());
    std::fwrite(noise.data(), 1, noise.size(), f);
    std::fflush(f);
  }
}

}  // namespace

// `--probe FILE [--part N]`: the function checks, as the mode says.
int probe(const std::string& file) {
  const std::string mode = env("FAKE_STUDENT_MODE");
  if (mode == "probe_garbage") {
    std::mt19937 rng(7);
    std::string bytes(4096, '\0');
    for (char& c : bytes) c = char(rng());
    std::ofstream(file, std::ios::binary) << bytes;
  } else if (mode == "probe_link") {
    // FAKE_STUDENT_MEAN is <refs>/<case>/mean.pfm.
    const std::string mean = env("FAKE_STUDENT_MEAN");
    const std::string refs = mean.substr(0, mean.rfind('/', mean.rfind('/') - 1));
    if (symlink((refs + "/probes.json").c_str(), file.c_str()) != 0) die("symlink failed");
  } else if (mode == "probe_huge") {
    std::ofstream out(file, std::ios::binary);
    const std::string block(1 << 20, '[');
    for (int i = 0; i < 20 && out; ++i) out << block << std::flush;
  } else if (mode == "probe_evil") {
    std::ofstream(file) << R"({"probes": [)"
                        << R"({"function": "generate_ray", "part": 1, "status": "crashed <script>alert(1)</script> EVIL", "checks": []},)"
                        << R"({"function": "intersect_sphere", "part": 1, "status": "ok", "checks": [)"
                        << R"({"name": "EVIL <b>", "abs": 1e30, "rel": 1e30, "values": [1]}]}]})";
  }
  return 0;
}

int main(int argc, char** argv) {
  if (argc >= 3 && std::string(argv[1]) == "--probe") return probe(argv[2]);
  const Args a = parse(argc, argv);
  const std::string mode = mode_of(a);
  const int w = a.width, h = a.height;
  if (mode.empty()) die("FAKE_STUDENT_MODE is not set");
  if (a.png.empty() || a.pfm.empty()) die("no -f or --pfm");

  if (mode == "good") {
    write_valid(a, w, h);
  } else if (mode == "crash") {
    raise(SIGSEGV);
  } else if (mode == "hang" || mode == "fork_hang") {
    int ready[2];
    if (pipe(ready) != 0) die("pipe failed");
    const bool hang = mode == "hang";
    fork_waiter(ready[1], false);
    if (!hang) fork_waiter(ready[1], true);
    close(ready[1]);
    await(ready[0], hang ? 1 : 3);
    if (hang) {
      record_self();
      wait_forever();
    }
    write_valid(a, w, h);
  } else if (mode == "garbage") {
    garbage();
  } else if (mode == "truncated_png") {
    const std::vector<unsigned char> png = png_bytes(image(w, h));
    write_bytes(a.png, png.data(), png.size() / 2);
    pt::write_pfm(a.pfm, image(w, h));
    write_stats(a, w, h);
  } else if (mode == "nan" || mode.rfind("probe_", 0) == 0) {
    pt::ImageBuffer img = image(w, h);
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    img.at(3, h - 1 - 2) = pt::Color(nan, 0.5f, 0.5f);  // rows from the bottom
    img.at(10, h - 1 - 9) = pt::Color(0.5f, inf, 0.5f);
    const std::vector<unsigned char> png = png_bytes(img);
    write_bytes(a.png, png.data(), png.size());
    pt::write_pfm(a.pfm, img);
    write_stats(a, w, h);
  } else if (mode == "wrong_size") {
    write_valid(a, w / 2, h / 2);
  } else if (mode == "wrong_size_pfm") {
    write_valid(a, w, h);
    pt::write_pfm(a.pfm, image(w / 2, h / 2));
  } else if (mode == "nothing") {
  } else if (mode == "no_pfm") {
    const std::vector<unsigned char> png = png_bytes(image(w, h));
    write_bytes(a.png, png.data(), png.size());
    write_stats(a, w, h);
  } else if (mode == "disk_fill") {
    FILE* f = std::fopen("fill.bin", "wb");
    if (!f) die("cannot create fill.bin");
    const std::vector<char> chunk(64 * 1024, 'x');
    for (size_t written = 0; written < (32u << 20); written += chunk.size())
      if (std::fwrite(chunk.data(), 1, chunk.size(), f) != chunk.size() || std::fflush(f) != 0) break;
    std::fclose(f);
    write_valid(a, w, h);
  } else if (mode == "disk_fill_many") {
    const std::vector<char> block(768 * 1024, 'x');
    for (int i = 0; i < 4; ++i) write_bytes("fill" + std::to_string(i) + ".bin", block.data(), block.size());
    write_valid(a, w, h);
  } else if (mode == "fifo") {
    if (mkfifo(a.png.c_str(), 0644) != 0) die("mkfifo failed: " + std::string(std::strerror(errno)));
    pt::write_pfm(a.pfm, image(w, h));
    write_stats(a, w, h);
  } else if (mode == "fifo_stats") {
    const pt::ImageBuffer img = image(w, h);
    const std::vector<unsigned char> png = png_bytes(img);
    write_bytes(a.png, png.data(), png.size());
    pt::write_pfm(a.pfm, img);
    if (a.stats.empty() || mkfifo(a.stats.c_str(), 0644) != 0) die("no --stats-json, or mkfifo failed");
  } else if (mode == "huge_pfm") {
    write_valid(a, w, h);
    std::string pfm = "PF\n60000 60000\n-1\n";
    pfm += std::string(48, '\0');
    write_bytes(a.pfm, pfm.data(), pfm.size());
  } else if (mode == "todo_hang") {
    record_self();  // first: the grader may kill it as soon as the line is out
    std::fprintf(stderr, "TODO: implement Part 1: generate_ray (stages/part1_raytracing/camera_rays.cpp)\n");
    std::fflush(stderr);
    wait_forever();
  } else if (mode == "todo_part2") {
    std::fprintf(stderr, "TODO: implement Part 2: BVH construction (stages/part2_bvh/bvh_build.cpp); using one leaf\n");
    std::fflush(stderr);
    write_valid(a, w, h);
  } else if (mode == "negative_roundoff" || mode == "negative") {
    pt::ImageBuffer img = image(w, h);
    img.at(5, 5).y = mode == "negative" ? -0.01f : -1e-6f;
    write_image(a, img);
    write_stats(a, w, h);
  } else if (mode == "costly") {
    write_image(a, image(w, h));
    write_stats(a, w, h, 100);
  } else if (mode == "costly_shadow") {
    write_image(a, image(w, h));
    write_stats(a, w, h, 2, 1, 100);
  } else if (mode == "uncounted") {
    write_image(a, image(w, h));
    write_stats(a, w, h, 0);
  } else if (mode == "exit3") {
    std::fprintf(stderr, "fake_student: giving up on purpose\n");
    return 3;
  } else {
    die("unknown FAKE_STUDENT_MODE '" + mode + "'");
  }
  return 0;
}
