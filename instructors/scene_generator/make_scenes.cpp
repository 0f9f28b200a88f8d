// make_scenes: writes the project's canonical scenes (scenes/*.dae) in the
// course's COLLADA dialect.
//
//   make_scenes [OPTIONS] OUTDIR         write every scene into OUTDIR
//   make_scenes --check [OPTIONS] OUTDIR exit 1 if a scene in OUTDIR is
//                                        missing or differs from what the
//                                        generator writes
// Options:
//   --sources DIR       the folder fetch_sources.sh filled (default:
//                       $PT_SCENE_SOURCES, else the repository's
//                       build/scene-sources)
//   --no-sources        build only the scenes that need no third-party data
//   --require-sources   fail (exit 1) if any scene had to be skipped
//
// The Cornell boxes and the analytic scenes are authored from published
// facts about the course's scenes (authored_scenes.h, from the blocks in
// scene_parts.h). The mesh scenes (mesh_scenes.h) are built from pinned
// third-party files (sources.txt, read by mesh_library.h): a scene whose
// sources are not in the cache is skipped, and said so; with --check its
// committed file must still exist. Every scene passes scene_checks.h before
// it is written. This file holds the scene list and the command line. See
// scenes/README.md for what each scene is for. Output is deterministic: the
// same generator and sources always write the same bytes.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

#include "instructors/scene_generator/authored_scenes.h"
#include "instructors/scene_generator/collada_writer.h"
#include "instructors/scene_generator/mesh_library.h"
#include "instructors/scene_generator/mesh_scenes.h"
#include "instructors/scene_generator/scene_checks.h"
#include "instructors/scene_generator/scene_model.h"
#include "instructors/scene_generator/sources.h"

#ifndef PT_SCENE_MANIFEST
#error "PT_SCENE_MANIFEST (the path of sources.txt) must be defined by the build"
#endif
#ifndef PT_SCENE_SOURCES_DEFAULT
#error "PT_SCENE_SOURCES_DEFAULT (the default source cache) must be defined by the build"
#endif

namespace fs = std::filesystem;
using namespace scenegen;

namespace {

// ---------------------------------------------------------------------------
// The scene list

struct Recipe {
  std::string file;
  std::vector<std::string> sources;  // files from sources.txt; none for authored scenes
  std::function<Scene(MeshLibrary&)> build;
};

std::vector<Recipe> all_recipes() {
  auto authored = [](Scene (*f)()) { return [f](MeshLibrary&) { return f(); }; };
  return {
      {"CBempty.dae", {}, authored(cb_empty)},
      {"CBspheres_lambertian.dae", {}, authored(cb_spheres_lambertian)},
      {"CBspheres.dae", {}, authored(cb_spheres)},
      {"CBglass_block.dae", {}, authored(cb_glass_block)},
      {"plane_arealight.dae", {}, authored(plane_arealight)},
      {"sphere_ambient.dae", {}, authored(sphere_ambient)},
      {"depth_order.dae", {}, authored(depth_order)},
      {"CBlights.dae", {}, authored(cb_lights)},
      {"CBbunny.dae", {"bunny00.off"}, cb_bunny},
      {"CBdragon.dae", {"dragon_vrip.ply"},
       [](MeshLibrary& lib) {
         return cb_dragon(lib, kDragonTriangles, "CBdragon.dae",
                          "Cornell box with the CGL area light and the Stanford dragon (100,000 triangles, diffuse 0.5)");
       }},
      {"CBdragon_large.dae", {"dragon_vrip.ply"},
       [](MeshLibrary& lib) {
         return cb_dragon(lib, kLargeDragonTriangles, "CBdragon_large.dae",
                          "Cornell box with the CGL area light and the Stanford dragon at 200,000 triangles, "
                          "a scene that needs a BVH");
       }},
      {"cow.dae", {"cow.off"}, cow},
      {"teapot.dae", {"TeapotGeometry.js"}, teapot},
      {"armadillo.dae", {"armadillo.off"}, armadillo},
      {"bunny_ambient.dae", {"bunny00.off"}, bunny_ambient},
      {"CBspheres_microfacet.dae", {}, authored(cb_spheres_microfacet)},
      {"CBspheres_dof.dae", {}, authored(cb_spheres_dof)},
      {"CBdragon_microfacet_au_0.005.dae", {"dragon_vrip.ply"},
       [](MeshLibrary& lib) { return cb_dragon_gold(lib, 0.005, "CBdragon_microfacet_au_0.005.dae"); }},
      {"CBdragon_microfacet_au_0.05.dae", {"dragon_vrip.ply"},
       [](MeshLibrary& lib) { return cb_dragon_gold(lib, 0.05, "CBdragon_microfacet_au_0.05.dae"); }},
      {"CBdragon_microfacet_au_0.25.dae", {"dragon_vrip.ply"},
       [](MeshLibrary& lib) { return cb_dragon_gold(lib, 0.25, "CBdragon_microfacet_au_0.25.dae"); }},
      {"CBdragon_microfacet_au_0.5.dae", {"dragon_vrip.ply"},
       [](MeshLibrary& lib) { return cb_dragon_gold(lib, 0.5, "CBdragon_microfacet_au_0.5.dae"); }},
      {"bunny_microfacet_envmap.dae", {"bunny00.off"}, bunny_microfacet_envmap},
  };
}

// ---------------------------------------------------------------------------
// Files

bool read_file(const fs::path& p, std::string& out) {
  std::ifstream in(p, std::ios::binary);
  if (!in) return false;
  out.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  return true;
}

// Write to a temporary name in the same directory, then rename over the
// target, so a reader never sees a half-written scene.
void write_atomically(const fs::path& target, const std::string& text) {
  const fs::path tmp = target.parent_path() / (target.filename().string() + ".tmp.make_scenes");
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error("cannot create " + tmp.string());
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
    out.close();
    if (!out) {
      std::error_code ec;
      fs::remove(tmp, ec);
      throw std::runtime_error("cannot write " + tmp.string());
    }
  }
  std::error_code ec;
  fs::rename(tmp, target, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw std::runtime_error("cannot rename " + tmp.string() + " to " + target.string() + ": " + ec.message());
  }
}

void usage(std::ostream& o) {
  o << "usage: make_scenes [--check] [--sources DIR | --no-sources] [--require-sources] OUTDIR\n"
       "  Writes the project's canonical scenes (COLLADA, course dialect) into OUTDIR.\n"
       "  --check            write nothing; exit 1 if a scene in OUTDIR is missing or out of date\n"
       "  --sources DIR      where fetch_sources.sh put the pinned mesh sources (default:\n"
       "                     $PT_SCENE_SOURCES, else " PT_SCENE_SOURCES_DEFAULT ")\n"
       "  --no-sources       only the scenes that need no third-party data\n"
       "  --require-sources  exit 1 if a scene is skipped because its sources are missing\n"
       "  Scenes whose sources are not fetched are skipped and listed; with --check their\n"
       "  files must still exist in OUTDIR.\n";
}

}  // namespace

int main(int argc, char** argv) {
  bool check = false, no_sources = false, require_sources = false;
  std::string outdir, sources_dir;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "-h" || a == "--help") {
      usage(std::cout);
      return 0;
    } else if (a == "--check") {
      check = true;
    } else if (a == "--no-sources") {
      no_sources = true;
    } else if (a == "--require-sources") {
      require_sources = true;
    } else if (a == "--sources") {
      if (i + 1 >= argc) {
        std::cerr << "make_scenes: --sources needs a folder\n";
        return 2;
      }
      sources_dir = argv[++i];
    } else if (!a.empty() && a[0] == '-') {
      std::cerr << "make_scenes: unknown option " << a << "\n";
      usage(std::cerr);
      return 2;
    } else if (outdir.empty()) {
      outdir = a;
    } else {
      std::cerr << "make_scenes: more than one OUTDIR given\n";
      usage(std::cerr);
      return 2;
    }
  }
  if (outdir.empty()) {
    usage(std::cerr);
    return 2;
  }
  if (no_sources && (!sources_dir.empty() || require_sources)) {
    std::cerr << "make_scenes: --no-sources cannot be combined with --sources or --require-sources\n";
    return 2;
  }
  if (!no_sources && sources_dir.empty()) {
    const char* env = std::getenv("PT_SCENE_SOURCES");
    sources_dir = env && *env ? env : PT_SCENE_SOURCES_DEFAULT;
  }

  try {
    const SourceSet sources(PT_SCENE_MANIFEST, no_sources ? std::string() : sources_dir);
    MeshLibrary library(sources);
    if (!check) fs::create_directories(outdir);
    int stale = 0;
    std::vector<std::string> skipped;
    for (const Recipe& r : all_recipes()) {
      const fs::path target = fs::path(outdir) / r.file;
      std::vector<std::string> absent;
      for (const std::string& name : r.sources)
        if (!sources.available(name)) absent.push_back(name);
      if (!absent.empty()) {
        std::string need;
        for (const std::string& n : absent) need += (need.empty() ? "" : ", ") + n;
        skipped.push_back(r.file);
        if (check && !fs::exists(target)) {
          std::cout << "missing: " << target.string() << " (and its sources: " << need << ")\n";
          ++stale;
        } else {
          std::cout << "skipped: " << r.file << " (needs " << need << ")\n";
        }
        continue;
      }
      Scene s = r.build(library);
      if (s.file != r.file) throw std::logic_error("recipe " + r.file + " built " + s.file);
      snap_to_file_precision(s);
      validate(s);
      const std::string text = write_collada(s);
      if (check) {
        std::string current;
        if (!read_file(target, current)) {
          std::cout << "missing: " << target.string() << "\n";
          ++stale;
        } else if (current != text) {
          std::cout << "out of date: " << target.string() << "\n";
          ++stale;
        } else {
          std::cout << "up to date: " << summary(s) << "\n";
        }
      } else {
        write_atomically(target, text);
        std::cout << "wrote " << target.string() << "  [" << summary(s) << "]\n";
      }
    }
    if (!skipped.empty())
      std::cout << skipped.size() << " scene(s) skipped: "
                << (no_sources ? std::string("--no-sources was given")
                               : "their sources are not in " + sources_dir + "/files") +
                       "; fetch them with instructors/scene_generator/fetch_sources.sh to "
                << (check ? "check" : "build") << " those too\n";
    if (stale) {
      std::cout << stale << " scene(s) missing or out of date; rebuild with make_scenes " << outdir
                << " (the mesh scenes need their sources: instructors/scene_generator/fetch_sources.sh)\n";
      return 1;
    }
    if (require_sources && !skipped.empty()) {
      std::cout << "make_scenes: --require-sources: " << skipped.size() << " scene(s) were skipped\n";
      return 1;
    }
  } catch (const std::exception& e) {
    std::cerr << "make_scenes: " << e.what() << "\n";
    return 2;
  }
  return 0;
}
