#include "viewer/file_access.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
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

// Whether the file at `path` has the course's camera settings format:
// its first six lines that are not blank hold 5, 6, 5, 9, 3 and 2 numbers
// and nothing else. Six lines of numbers written with 17 digits take less
// than a kilobyte: a longer file is not one, and is not read beyond this.
constexpr size_t kMaxCameraFileBytes = 16 << 10;

bool looks_like_camera_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  std::string text(kMaxCameraFileBytes + 1, '\0');
  in.read(text.data(), std::streamsize(text.size()));
  text.resize(size_t(in.gcount()));
  if (text.size() > kMaxCameraFileBytes || text.find('\0') != std::string::npos) return false;
  const int counts[6] = {5, 6, 5, 9, 3, 2};
  std::istringstream lines(text);
  std::string line;
  int rows = 0;
  while (rows < 6 && std::getline(lines, line)) {
    std::istringstream tokens(line);
    std::string tok;
    int n = 0;
    while (tokens >> tok) {
      char* end = nullptr;
      const double v = std::strtod(tok.c_str(), &end);
      if (end != tok.c_str() + tok.size() || !std::isfinite(v)) return false;
      ++n;
    }
    if (n == 0) continue;
    if (n != counts[rows]) return false;
    ++rows;
  }
  return rows == 6;
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
  // Missing and outside the folders get the same answer: the page learns
  // nothing about files elsewhere, not even whether they exist.
  const std::string refused = requested + ": not a file the viewer may open (" +
                              (kind == FileKind::Scene         ? "a .dae scene"
                               : kind == FileKind::Environment ? "an .exr environment map"
                                                               : "a camera settings file") +
                              " inside the folders the viewer was started with)";
  if (requested.empty() || requested.size() > 4096 || requested.find('\0') != std::string::npos) {
    *why = "no file named";
    return "";
  }
  const auto allowed = [&](const fs::path& p) {
    for (const std::string& r : roots_)
      if (inside(p, fs::path(r))) return true;
    return false;
  };
  std::error_code ec;
  const fs::path c = fs::canonical(requested, ec);  // follows every link; fails when missing
  if (ec) {
    // Missing: said so only inside the folders (links followed as far as
    // they exist).
    const fs::path w = fs::weakly_canonical(requested, ec);
    *why = !ec && allowed(w) ? requested + ": no such file" : refused;
    return "";
  }
  if (!allowed(c)) {
    *why = refused;
    return "";
  }
  if (!fs::is_regular_file(c, ec)) {
    *why = requested + ": not a file";
    return "";
  }
  // A camera file is read by the renderer, whose errors quote what they
  // read: only a file that has the course's format gets that far.
  if (!has_kind(c, kind) || (kind == FileKind::Camera && !looks_like_camera_file(c))) {
    *why = requested + (kind == FileKind::Scene         ? ": not a .dae scene"
                        : kind == FileKind::Environment ? ": not an .exr environment map"
                                                        : ": not a camera settings file (the course's six lines of numbers)");
    return "";
  }
  return c.string();
}

std::vector<std::string> FileAccess::list(FileKind kind, size_t limit) const {
  std::vector<std::string> out;
  for (const std::string& r : roots_) {
    std::error_code ec;
    fs::recursive_directory_iterator it(r, fs::directory_options::skip_permission_denied, ec), end;
    // A folder as large as / (--allow /) is looked at only so far.
    size_t seen = 0;
    for (; !ec && it != end && out.size() < limit && ++seen <= 50 * limit; it.increment(ec)) {
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
