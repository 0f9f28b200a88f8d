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
  // of `kind` inside an allowed folder once every symbolic link is
  // followed: a .dae scene, an .exr map, or a camera file (.txt, .cam or
  // no extension) whose first six lines hold the course's 5, 6, 5, 9, 3
  // and 2 numbers. Otherwise an empty string and *why says what is wrong,
  // quoting nothing from the file; a missing file and one outside the
  // folders get the same answer (a file missing inside them: "no such
  // file").
  std::string resolve(const std::string& requested, FileKind kind, std::string* why) const;

  // Files of `kind` in the allowed folders (three levels deep, at most
  // `limit` of them, among the first 50 x `limit` entries), resolved, sorted.
  std::vector<std::string> list(FileKind kind, size_t limit = 2000) const;

 private:
  std::vector<std::string> roots_;
};

}  // namespace pt::viewer
