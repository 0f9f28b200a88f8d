#include "viewer/viewer_cases.h"

#include <cstdio>
#include <filesystem>

#include "viewer/requests.h"

namespace pt::viewer {

std::vector<ViewerCase> load_cases(const std::string& source_dir, const FileAccess& files) {
  std::vector<ViewerCase> out;
  std::vector<grader::Case> cases;
  try {
    cases = grader::read_cases(source_dir + "/grader/cases.txt");
  } catch (const std::exception&) {
    return out;
  }
  for (const grader::Case& c : cases) {
    if (c.kind != grader::CaseKind::Image) continue;
    std::vector<std::string> args = {"viewer", "--part", std::to_string(c.part)};
    args.insert(args.end(), c.options.begin(), c.options.end());
    args.push_back(source_dir + "/scenes/" + c.scene);
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    ViewerCase v;
    v.c = c;
    if (parse_command_line(int(argv.size()), argv.data(), &v.opts)) continue;
    std::string why;
    const std::string scene = files.resolve(v.opts.scene_path, FileKind::Scene, &why);
    v.available = !scene.empty();
    if (v.available) v.opts.scene_path = scene;
    out.push_back(v);
  }
  return out;
}

grader::Catalogue load_catalogue(const std::string& source_dir) {
  const std::string path = source_dir + "/grader/known_bugs.json";
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return {};
  try {
    return grader::read_catalogue(path);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "viewer: warning: %s (the difference overlay names no likely causes)\n", e.what());
    return {};
  }
}

const ViewerCase* find_case(const std::vector<ViewerCase>& cases, const std::string& name) {
  const ViewerCase* vc = nullptr;
  for (const ViewerCase& x : cases)
    if (x.c.name == name) vc = &x;
  return vc;
}

std::string image_key(RenderOptions o) {
  o.threads = 1;
  o.seed = 0;
  o.bvh_max_leaf = 4;
  o.bvh_bins = 12;
  o.adaptive_set = true;
  const std::vector<std::string> f = render_flags(o);
  std::string k;
  for (const std::string& a : f) k += a + " ";
  return k;
}

}  // namespace pt::viewer
