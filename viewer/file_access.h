// Which files the page may open: scene, camera and environment files under
// the folders named on the command line, and nothing else.
#pragma once
#include <string>
#include <vector>

namespace pt::viewer {

enum class FileKind { Scene, Camera, Environment };

class FileAccess {
 public:
  // Allows the folder `dir` (resolved: symbolic links followed, "." and ".."
  // removed). Throws std::runtime_error when it is not a folder.
  void allow_folder(const std::string& dir);
  const std::vector<std::string>& folders() const { return roots_; }

  // The resolved path of `requested` when it names an existing regular file
  // of `kind` (.dae; any name for a camera file; .exr) inside an allowed
  // folder once every symbolic link is followed; otherwise an empty string
  // and *why says what is wrong.
  std::string resolve(const std::string& requested, FileKind kind, std::string* why) const;

  // Files of `kind` in the allowed folders (three levels deep, at most
  // `limit` of them), resolved, sorted.
  std::vector<std::string> list(FileKind kind, size_t limit = 2000) const;

 private:
  std::vector<std::string> roots_;
};

}  // namespace pt::viewer
