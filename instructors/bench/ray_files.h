// The two files the ray benchmark shares with the Embree harness
// (../shared/bench/embree_bench.cpp), so that both engines trace identical
// work. Little-endian:
//
//   NAME.tris  "PTTRIS01" | uint64 n | n x 9 float32   v0.xyz v1.xyz v2.xyz (world space)
//   NAME.rays  "PTRAYS01" | uint64 n | n x 8 float32   o.xyz d.xyz tmin tmax
#pragma once
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/ray.h"
#include "common/scene.h"

namespace pt::bench {

// One record of a .rays file, laid out exactly as in the file.
struct RayRecord {
  float o[3];
  float d[3];
  float tmin;
  float tmax;

  Ray to_ray() const { return Ray(Vec3(o[0], o[1], o[2]), Vec3(d[0], d[1], d[2]), tmin, tmax); }
  static RayRecord from(const Vec3& o, const Vec3& d, float tmin, float tmax) {
    return RayRecord{{o.x, o.y, o.z}, {d.x, d.y, d.z}, tmin, tmax};
  }
};
static_assert(sizeof(RayRecord) == 32, "a .rays record is 8 float32");

namespace detail {

inline bool little_endian() {
  const uint16_t one = 1;
  unsigned char first = 0;
  std::memcpy(&first, &one, 1);
  return first == 1;
}

// Writes magic, count and `bytes` bytes of payload; throws naming the file.
inline void write_file(const std::string& path, const char magic[8], uint64_t count, const void* data,
                       size_t bytes) {
  if (!little_endian()) throw std::runtime_error(path + ": the file formats are little-endian only");
  FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) throw std::runtime_error(path + ": cannot open for writing");
  bool ok = std::fwrite(magic, 1, 8, f) == 8 && std::fwrite(&count, sizeof(count), 1, f) == 1 &&
            (bytes == 0 || std::fwrite(data, 1, bytes, f) == bytes);
  ok = (std::fclose(f) == 0) && ok;
  if (!ok) throw std::runtime_error(path + ": write failed (disk full?)");
}

}  // namespace detail

// The scene's triangles in scene order (spheres cannot be written).
inline void write_tris(const std::string& path, const Scene& scene) {
  std::vector<float> v;
  v.reserve(scene.triangles.size() * 9);
  for (const Triangle& t : scene.triangles)
    for (const Vec3* p : {&t.p1, &t.p2, &t.p3}) {
      v.push_back(p->x);
      v.push_back(p->y);
      v.push_back(p->z);
    }
  detail::write_file(path, "PTTRIS01", scene.triangles.size(), v.data(), v.size() * sizeof(float));
}

inline void write_rays(const std::string& path, const std::vector<RayRecord>& rays) {
  detail::write_file(path, "PTRAYS01", rays.size(), rays.data(), rays.size() * sizeof(RayRecord));
}

}  // namespace pt::bench
