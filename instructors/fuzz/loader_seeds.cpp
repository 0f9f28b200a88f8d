// The seeds of fuzz_loaders (see loader_seeds.h).
#include "instructors/fuzz/loader_seeds.h"

#include <ImfRgbaFile.h>
#include <ImfTiledRgbaFile.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace fs = std::filesystem;

namespace fuzz {

std::string slurp(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::ostringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

Kind kind_of(const fs::path& p) {
  const std::string ext = p.extension().string();
  if (ext == ".dae") return Kind::Scene;
  if (ext == ".exr") return Kind::Exr;
  return Kind::Camera;
}

// Small OpenEXR files in every compression and layout, written here so that
// the mutations reach each decoder.
void write_exr_seeds(const std::string& dir, std::vector<Seed>* seeds) {
  const int w = 12, h = 5;
  std::vector<Imf::Rgba> px(size_t(w * h));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) px[size_t(y * w + x)] = Imf::Rgba(0.1f * float(x), 0.2f * float(y), 0.5f, 1.0f);
  const std::pair<Imf::Compression, const char*> schemes[] = {
      {Imf::NO_COMPRESSION, "none"}, {Imf::RLE_COMPRESSION, "rle"},   {Imf::ZIPS_COMPRESSION, "zips"},
      {Imf::ZIP_COMPRESSION, "zip"}, {Imf::PIZ_COMPRESSION, "piz"},   {Imf::PXR24_COMPRESSION, "pxr24"},
      {Imf::B44_COMPRESSION, "b44"}, {Imf::B44A_COMPRESSION, "b44a"}, {Imf::DWAA_COMPRESSION, "dwaa"}};
  for (const auto& [c, name] : schemes) {
    const std::string path = dir + "/seed-" + name + ".exr";
    {
      Imf::RgbaOutputFile f(path.c_str(), w, h, Imf::WRITE_RGB, 1, Imath::V2f(0, 0), 1, Imf::INCREASING_Y, c);
      f.setFrameBuffer(px.data(), 1, size_t(w));
      f.writePixels(h);
    }
    seeds->push_back({std::string("generated ") + name + ".exr", Kind::Exr, slurp(path)});
  }
  {
    const std::string path = dir + "/seed-luminance.exr";
    {
      Imf::RgbaOutputFile f(path.c_str(), w, h, Imf::WRITE_Y);
      f.setFrameBuffer(px.data(), 1, size_t(w));
      f.writePixels(h);
    }
    seeds->push_back({"generated luminance.exr", Kind::Exr, slurp(path)});
  }
  {
    const std::string path = dir + "/seed-tiled.exr";
    {
      Imf::TiledRgbaOutputFile f(path.c_str(), w, h, 4, 4, Imf::MIPMAP_LEVELS, Imf::ROUND_DOWN, Imf::WRITE_RGBA);
      f.setFrameBuffer(px.data(), 1, size_t(w));
      for (int level = 0; level < f.numLevels(); ++level)
        f.writeTiles(0, f.numXTiles(level) - 1, 0, f.numYTiles(level) - 1, level);
    }
    seeds->push_back({"generated tiled.exr", Kind::Exr, slurp(path)});
  }
}

}  // namespace fuzz
