#include "viewer/file_access.h"

#include <algorithm>
#include <filesystem>
#include <stdexcept>
#include <system_error>

namespace pt::viewer {

namespace fs = std::filesystem;

namespace {

bool has_kind(const fs::path& p, FileKind kind) {
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  switch (kind) {
    case FileKind::Scene: return ext == ".dae";
    case FileKind::Environment: return ext == ".exr";
    case FileKind::Camera: return ext == ".txt" || ext == ".cam" || ext.empty();
  }
  return false;
}

// Whether `p` lies inside `root` (both resolved), compared by components.
bool inside(const fs::path& p, const fs::path& root) {
  auto pi = p.begin();
  for (auto ri = root.begin(); ri != root.end(); ++ri, ++pi) {
    if (ri->empty()) continue;  // a trailing separator
    if (pi == p.end() || *pi != *ri) return false;
  }
  return true;
}

}  // namespace

void FileAccess::allow_folder(const std::string& dir) {
  std::error_code ec;
  const fs::path c = fs::canonical(dir.empty() ? "." : dir, ec);
  if (ec || !fs::is_directory(c, ec)) throw std::runtime_error(dir + ": not a folder");
  if (std::find(roots_.begin(), roots_.end(), c.string()) == roots_.end()) roots_.push_back(c.string());
}

std::string FileAccess::resolve(const std::string& requested, FileKind kind, std::string* why) const {
  if (requested.empty() || requested.size() > 4096 || requested.find('\0') != std::string::npos) {
    *why = "no file named";
    return "";
  }
  std::error_code ec;
  const fs::path c = fs::canonical(requested, ec);  // follows every link; fails when missing
  if (ec) {
    *why = requested + ": no such file";
    return "";
  }
  bool ok = false;
  for (const std::string& r : roots_) ok = ok || inside(c, fs::path(r));
  if (!ok) {
    *why = requested + ": outside the folders the viewer was started with";
    return "";
  }
  if (!fs::is_regular_file(c, ec)) {
    *why = requested + ": not a file";
    return "";
  }
  if (!has_kind(c, kind)) {
    *why = requested + (kind == FileKind::Scene ? ": not a .dae scene" : kind == FileKind::Environment
                                                                              ? ": not an .exr environment map"
                                                                              : ": not a camera settings file (.txt)");
    return "";
  }
  return c.string();
}

std::vector<std::string> FileAccess::list(FileKind kind, size_t limit) const {
  std::vector<std::string> out;
  for (const std::string& r : roots_) {
    std::error_code ec;
    fs::recursive_directory_iterator it(r, fs::directory_options::skip_permission_denied, ec), end;
    for (; !ec && it != end && out.size() < limit; it.increment(ec)) {
      if (it.depth() >= 3) it.disable_recursion_pending();
      std::string why;
      if (!has_kind(it->path(), kind)) continue;
      const std::string c = resolve(it->path().string(), kind, &why);
      if (!c.empty()) out.push_back(c);
    }
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

}  // namespace pt::viewer
