// The pinned third-party source files some scenes are built from.
//
// sources.txt (next to this file) lists every archive (Debian or npm
// package, with version and SHA-256) and every file taken out of one (with
// its own SHA-256). fetch_sources.sh downloads the archives into a cache
// folder outside the repository and extracts the files into its files/
// subfolder; the generator reads them from there and refuses any whose
// SHA-256 differs from the manifest, so a scene built from sources is always
// built from exactly the pinned bytes.
#pragma once
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "instructors/scene_generator/sha256.h"

namespace scenegen {

struct SourceFile {
  std::string name;     // file name under <cache>/files/
  std::string sha256;
  std::string archive;  // the archive id it is extracted from
};

class SourceSet {
 public:
  // `dir` is the cache folder; an empty `dir` means "no sources".
  SourceSet(const std::string& manifest_path, std::string dir) : dir_(std::move(dir)) {
    std::ifstream in(manifest_path);
    if (!in) throw std::runtime_error("cannot read the source manifest " + manifest_path);
    std::string line;
    int n = 0;
    while (std::getline(in, line)) {
      ++n;
      std::istringstream ls(line);
      std::string kind;
      if (!(ls >> kind) || kind[0] == '#') continue;
      if (kind == "file") {
        SourceFile f;
        if (!(ls >> f.name >> f.sha256 >> f.archive) || f.sha256.size() != 64)
          throw std::runtime_error(manifest_path + ":" + std::to_string(n) + ": malformed file line");
        files_[f.name] = f;
      } else if (kind != "archive") {
        throw std::runtime_error(manifest_path + ":" + std::to_string(n) + ": unknown entry '" + kind + "'");
      }
    }
  }

  const std::string& dir() const { return dir_; }
  std::string path(const std::string& name) const { return dir_ + "/files/" + name; }

  // Whether the file is listed and present (its contents are checked when read).
  bool available(const std::string& name) const {
    if (files_.count(name) == 0) throw std::logic_error("source " + name + " is not in the manifest");
    if (dir_.empty()) return false;
    std::ifstream f(path(name), std::ios::binary);
    return bool(f);
  }

  // The file's bytes, after checking them against the pinned SHA-256.
  std::string read(const std::string& name) const {
    const auto it = files_.find(name);
    if (it == files_.end()) throw std::logic_error("source " + name + " is not in the manifest");
    std::ifstream f(path(name), std::ios::binary);
    if (!f) throw std::runtime_error("cannot read source " + path(name));
    std::string data((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    const std::string sum = sha256_hex(data);
    if (sum != it->second.sha256)
      throw std::runtime_error("source " + path(name) + " has SHA-256 " + sum + ", but sources.txt pins " +
                               it->second.sha256 + "; run instructors/scene_generator/fetch_sources.sh again");
    return data;
  }

 private:
  std::string dir_;
  std::map<std::string, SourceFile> files_;
};

}  // namespace scenegen
