// Mesh decimation by quadric-error edge collapse (after Garland and
// Heckbert, "Surface simplification using quadric error metrics",
// SIGGRAPH 1997), written for the generator.
//
// Input: a closed, consistently wound, edge-manifold triangle mesh. Each
// collapse merges the two ends of one edge into a single vertex at the
// position that minimises the summed squared distances to the planes of the
// original triangles around them (area-weighted quadrics), and removes the
// two triangles on the edge. A collapse is refused if it would make the mesh
// non-manifold (link condition) or turn any remaining triangle over, so the
// result stays closed and keeps its orientation.
//
// Deterministic: ties between equal costs are broken by vertex indices, no
// hashing or pointer order is involved, and the output keeps the surviving
// vertices and triangles in their original order.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <queue>
#include <stdexcept>
#include <string>
#include <vector>

#include "instructors/scene_generator/mesh_tools.h"

namespace scenegen {

namespace qem {

// A symmetric 4x4 matrix stored as its upper triangle:
// a00 a01 a02 a03 a11 a12 a13 a22 a23 a33.
struct Quadric {
  std::array<double, 10> a{};
  Quadric& operator+=(const Quadric& o) {
    for (int i = 0; i < 10; ++i) a[size_t(i)] += o.a[size_t(i)];
    return *this;
  }
  // The plane n . p + d = 0 (unit n), weighted by w.
  static Quadric plane(V3 n, double d, double w) {
    Quadric q;
    const double p[4] = {n.x, n.y, n.z, d};
    int k = 0;
    for (int i = 0; i < 4; ++i)
      for (int j = i; j < 4; ++j) q.a[size_t(k++)] = w * p[i] * p[j];
    return q;
  }
  double error(V3 v) const {
    const double x = v.x, y = v.y, z = v.z;
    const double e = a[0] * x * x + 2 * a[1] * x * y + 2 * a[2] * x * z + 2 * a[3] * x + a[4] * y * y +
                     2 * a[5] * y * z + 2 * a[6] * y + a[7] * z * z + 2 * a[8] * z + a[9];
    return std::max(e, 0.0);
  }
};

struct Candidate {
  double cost;
  int a, b;            // a < b; b is merged into a
  uint32_t sa, sb;     // the vertices' versions when this entry was made
  V3 pos;
  bool operator>(const Candidate& o) const {
    if (cost != o.cost) return cost > o.cost;
    if (a != o.a) return a > o.a;
    return b > o.b;
  }
};

class Decimator {
 public:
  explicit Decimator(const IndexedMesh& m) : v_(m.v), t_(m.t) {
    const Topology topo = topology(m);
    if (!topo.closed())
      throw std::runtime_error("decimate: the input mesh is not closed and consistently wound");
    const Box3 b = bounds(m);
    scale_ = length(b.extent());
    alive_t_.assign(t_.size(), 1);
    alive_v_.assign(v_.size(), 1);
    version_.assign(v_.size(), 0);
    q_.assign(v_.size(), Quadric());
    vt_.assign(v_.size(), {});
    for (size_t i = 0; i < t_.size(); ++i) {
      for (int k : t_[i]) vt_[size_t(k)].push_back(int(i));
      const V3 p0 = v_[size_t(t_[i][0])];
      const V3 n = cross(v_[size_t(t_[i][1])] - p0, v_[size_t(t_[i][2])] - p0);
      const double len = length(n);
      if (len == 0) throw std::runtime_error("decimate: the input has a zero-area triangle");
      const V3 u = (1.0 / len) * n;
      const Quadric q = Quadric::plane(u, -dot(u, p0), 0.5 * len);
      for (int k : t_[i]) q_[size_t(k)] += q;
    }
    live_triangles_ = t_.size();
    for (size_t i = 0; i < t_.size(); ++i)
      for (int k = 0; k < 3; ++k) {
        const int a = t_[i][size_t(k)], b = t_[i][size_t((k + 1) % 3)];
        if (a < b) push(a, b);  // each closed-mesh edge appears once with a < b
      }
  }

  size_t triangles() const { return live_triangles_; }

  // Collapses edges until at most `target` triangles remain. Returns false
  // if no further collapse is allowed before that.
  bool run_to(size_t target) {
    while (live_triangles_ > target) {
      if (heap_.empty()) return false;
      const Candidate c = heap_.top();
      heap_.pop();
      if (!alive_v_[size_t(c.a)] || !alive_v_[size_t(c.b)] || version_[size_t(c.a)] != c.sa ||
          version_[size_t(c.b)] != c.sb)
        continue;
      collapse_if_allowed(c);
    }
    return true;
  }

  IndexedMesh result() const {
    IndexedMesh m;
    m.v = v_;
    for (size_t i = 0; i < t_.size(); ++i)
      if (alive_t_[i]) m.t.push_back(t_[i]);
    return drop_unused_vertices(m);
  }

 private:
  void push(int a, int b) {
    Quadric q = q_[size_t(a)];
    q += q_[size_t(b)];
    const V3 pa = v_[size_t(a)], pb = v_[size_t(b)];
    V3 best = 0.5 * (pa + pb);
    double cost = q.error(best);
    // The minimiser of the quadric, when the system is well conditioned and
    // the point stays near the edge.
    const auto& x = q.a;
    const double m00 = x[0], m01 = x[1], m02 = x[2], m11 = x[4], m12 = x[5], m22 = x[7];
    const double r0 = -x[3], r1 = -x[6], r2 = -x[8];
    const double c00 = m11 * m22 - m12 * m12, c01 = m02 * m12 - m01 * m22, c02 = m01 * m12 - m02 * m11;
    const double det = m00 * c00 + m01 * c01 + m02 * c02;
    const double mag = std::max({std::fabs(m00), std::fabs(m11), std::fabs(m22), 1e-300});
    bool solved = false;
    if (std::fabs(det) > 1e-9 * mag * mag * mag) {
      const double c11 = m00 * m22 - m02 * m02, c12 = m01 * m02 - m00 * m12, c22 = m00 * m11 - m01 * m01;
      const V3 s{(c00 * r0 + c01 * r1 + c02 * r2) / det, (c01 * r0 + c11 * r1 + c12 * r2) / det,
                 (c02 * r0 + c12 * r1 + c22 * r2) / det};
      if (length(s - best) <= length(pb - pa)) {
        best = s;
        cost = q.error(s);
        solved = true;
      }
    }
    if (!solved) {
      for (const V3& p : {pa, pb}) {
        const double e = q.error(p);
        if (e < cost) {
          cost = e;
          best = p;
        }
      }
    }
    heap_.push(Candidate{cost, a, b, version_[size_t(a)], version_[size_t(b)], best});
  }

  // The distinct vertices adjacent to `a` (sorted).
  std::vector<int> neighbours(int a) const {
    std::vector<int> n;
    for (int ti : vt_[size_t(a)])
      for (int k : t_[size_t(ti)])
        if (k != a) n.push_back(k);
    std::sort(n.begin(), n.end());
    n.erase(std::unique(n.begin(), n.end()), n.end());
    return n;
  }

  static bool has(const Tri& t, int x) { return t[0] == x || t[1] == x || t[2] == x; }

  void collapse_if_allowed(const Candidate& c) {
    const int a = c.a, b = c.b;
    // The two triangles on the edge and their third vertices.
    std::vector<int> shared;
    for (int ti : vt_[size_t(a)])
      if (has(t_[size_t(ti)], b)) shared.push_back(ti);
    if (shared.size() != 2) return;
    int opp[2];
    for (int s = 0; s < 2; ++s) {
      const Tri& t = t_[size_t(shared[size_t(s)])];
      opp[s] = t[0] != a && t[0] != b ? t[0] : t[1] != a && t[1] != b ? t[1] : t[2];
    }
    if (opp[0] == opp[1]) return;
    // Link condition: a and b may share no neighbour but the two opposite
    // vertices, or the collapse would pinch the surface.
    const std::vector<int> na = neighbours(a), nb = neighbours(b);
    std::vector<int> common;
    std::set_intersection(na.begin(), na.end(), nb.begin(), nb.end(), std::back_inserter(common));
    if (common.size() != 2) return;
    if (!((common[0] == opp[0] && common[1] == opp[1]) || (common[0] == opp[1] && common[1] == opp[0]))) return;
    // No triangle around a or b may turn over or degenerate.
    for (int end : {a, b})
      for (int ti : vt_[size_t(end)]) {
        const Tri& t = t_[size_t(ti)];
        if (has(t, a) && has(t, b)) continue;
        V3 p[3], q[3];
        for (int k = 0; k < 3; ++k) {
          p[k] = v_[size_t(t[size_t(k)])];
          q[k] = t[size_t(k)] == end ? c.pos : p[k];
        }
        const V3 n0 = cross(p[1] - p[0], p[2] - p[0]), n1 = cross(q[1] - q[0], q[2] - q[0]);
        const double l0 = length(n0), l1 = length(n1);
        if (l1 <= 1e-14 * scale_ * scale_) return;
        if (dot(n0, n1) < 0.2 * l0 * l1) return;
      }

    // Collapse b into a.
    for (int ti : shared) {
      alive_t_[size_t(ti)] = 0;
      --live_triangles_;
      for (int k : t_[size_t(ti)]) {
        auto& list = vt_[size_t(k)];
        list.erase(std::remove(list.begin(), list.end(), ti), list.end());
      }
    }
    for (int ti : vt_[size_t(b)]) {
      for (int& k : t_[size_t(ti)])
        if (k == b) k = a;
      vt_[size_t(a)].push_back(ti);
    }
    std::sort(vt_[size_t(a)].begin(), vt_[size_t(a)].end());
    vt_[size_t(b)].clear();
    alive_v_[size_t(b)] = 0;
    v_[size_t(a)] = c.pos;
    q_[size_t(a)] += q_[size_t(b)];
    ++version_[size_t(a)];
    for (int n : neighbours(a)) {
      if (n < a) push(n, a);
      else push(a, n);
    }
  }

  std::vector<V3> v_;
  std::vector<Tri> t_;
  std::vector<char> alive_t_, alive_v_;
  std::vector<uint32_t> version_;
  std::vector<Quadric> q_;
  std::vector<std::vector<int>> vt_;  // triangles around each vertex
  std::priority_queue<Candidate, std::vector<Candidate>, std::greater<Candidate>> heap_;
  size_t live_triangles_ = 0;
  double scale_ = 1;
};

}  // namespace qem

// Decimates a closed mesh to each of `targets` (descending triangle counts)
// in one pass, returning one mesh per target. Each target must be reachable
// exactly (a collapse removes two triangles, so keep the parity of the
// input's count).
inline std::vector<IndexedMesh> decimate(const IndexedMesh& m, const std::vector<size_t>& targets) {
  qem::Decimator d(m);
  std::vector<IndexedMesh> out;
  for (size_t target : targets) {
    if (!d.run_to(target) || d.triangles() != target)
      throw std::runtime_error("decimate: could not reach " + std::to_string(target) + " triangles (stopped at " +
                               std::to_string(d.triangles()) + ")");
    out.push_back(d.result());
  }
  return out;
}

}  // namespace scenegen
