// The primitive readers (see primitive_lists.h).
#include "common/collada/primitive_lists.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "common/collada.h"
#include "common/collada/xml_values.h"

namespace pt::collada {

namespace {

constexpr int kMaxInputOffset = 4096;  // larger offsets are certainly corrupt

// The <input>s of a primitive list: how many indices each vertex has, which
// of them is the position's, and how large each may be.
struct InputLayout {
  int stride = 0;
  int vertex_offset = -1;
  const XMLElement* vertex_input = nullptr;
  std::vector<uint64_t> limit;                  // offset -> the smallest element count among its inputs
  std::vector<const XMLElement*> limit_source;  // the source giving it, for messages
};

// Reads one primitive list.
class ListReader {
 public:
  ListReader(const XMLElement* prim, const PrimitiveListContext& ctx, MeshPrimitives& mesh)
      : prim_(prim), ctx_(ctx), msg_(ctx.msg), mesh_(mesh) {}

  void read();

 private:
  void read_inputs();
  void read_input(const XMLElement* in);
  size_t read_indices(const XMLElement* p, uint64_t expected = 0);
  void check_indices(const XMLElement* p, size_t from, size_t to) const;
  void add_polygon(size_t first, size_t n);
  void read_triangles();
  std::vector<long long> read_vertex_counts(const XMLElement* vc, uint64_t* needed) const;
  void read_polylist();
  void read_polygons();

  const XMLElement* prim_;
  const PrimitiveListContext& ctx_;
  Messages& msg_;
  MeshPrimitives& mesh_;
  InputLayout layout_;
  bool has_count_ = false;
  uint64_t count_ = 0;
  int material_ = 0;
  std::vector<long long> idx_;  // the indices read, `stride` per vertex
  std::string buf_;
};

void ListReader::read() {
  const std::string_view kind = prim_->Name();
  if (kind == "triangles")
    msg_.check_children(prim_, {"input", "p", "extra"});
  else if (kind == "polylist")
    msg_.check_children(prim_, {"input", "vcount", "p", "extra"});
  else
    msg_.check_children(prim_, {"input", "p", "ph", "extra"});
  read_inputs();
  has_count_ = count_attribute(msg_, prim_, "count", &count_);
  material_ = ctx_.material_of(prim_->Attribute("material"));
  if (kind == "triangles")
    read_triangles();
  else if (kind == "polylist")
    read_polylist();
  else
    read_polygons();
}

void ListReader::read_inputs() {
  for (const XMLElement* in = prim_->FirstChildElement("input"); in; in = in->NextSiblingElement("input"))
    read_input(in);
  if (!layout_.vertex_input) msg_.fail(prim_, "has no <input semantic=\"VERTEX\">");
}

void ListReader::read_input(const XMLElement* in) {
  InputLayout& l = layout_;
  const char* sem = in->Attribute("semantic");
  if (!sem) msg_.fail(in, "missing the semantic attribute");
  uint64_t off = 0;
  count_attribute(msg_, in, "offset", &off);
  if (off > uint64_t(kMaxInputOffset)) msg_.fail(in, "offset " + std::to_string(off) + " is too large");
  const int o = int(off);
  if (o + 1 > l.stride) {
    l.stride = o + 1;
    l.limit.resize(size_t(l.stride), std::numeric_limits<uint64_t>::max());
    l.limit_source.resize(size_t(l.stride), nullptr);
  }
  uint64_t n = 0;
  const XMLElement* src = nullptr;
  if (std::strcmp(sem, "VERTEX") == 0) {
    if (l.vertex_input) msg_.fail(in, "a second VERTEX input");
    l.vertex_input = in;
    l.vertex_offset = o;
    src = ctx_.sources.position_source(in);
    if (mesh_.position_source && mesh_.position_source != src)
      msg_.fail(in, "refers to other positions than the rest of the mesh; a mesh has one <vertices>");
    mesh_.position_source = src;
    n = ctx_.sources.positions(src).count();
  } else {
    src = ctx_.doc.resolve(in, "source", "source");
    n = ctx_.sources.element_count(src);
  }
  if (n < l.limit[size_t(o)]) {
    l.limit[size_t(o)] = n;
    l.limit_source[size_t(o)] = src;
  }
}

// Parses one <p>, appending to idx_; returns how many indices it added.
size_t ListReader::read_indices(const XMLElement* p, uint64_t expected) {
  const std::string_view s = element_text(p, buf_);
  idx_.reserve(idx_.size() + size_t(std::min<uint64_t>(expected, max_numbers(s))));
  const size_t before = idx_.size();
  std::string_view bad;
  if (!parse_list(s, idx_, &bad)) msg_.fail(p, quote(bad) + " is not an index");
  return idx_.size() - before;
}

// Checks the indices [from, to) of idx_ against their sources.
void ListReader::check_indices(const XMLElement* p, size_t from, size_t to) const {
  const InputLayout& l = layout_;
  for (size_t k = from; k < to; ++k) {
    const size_t o = (k - from) % size_t(l.stride);
    const long long v = idx_[k];
    if (v < 0)
      msg_.fail(p, "index " + std::to_string(v) + " (number " + std::to_string(k - from) + " in <p>) is negative");
    if (uint64_t(v) >= l.limit[o])
      msg_.fail(p, "index " + std::to_string(v) + " (number " + std::to_string(k - from) +
                       " in <p>) is out of range for " + msg_.describe(l.limit_source[o]) + ", which has " +
                       std::to_string(l.limit[o]) + " elements");
  }
}

// Fan-triangulates a polygon of n vertices whose indices start at `first`.
void ListReader::add_polygon(size_t first, size_t n) {
  MeshTriangles& out = mesh_.triangles;
  check_primitive_limit(msg_, prim_, ctx_.scene_primitives, out.corners.size() + (n - 2));
  const size_t stride = size_t(layout_.stride), vertex_offset = size_t(layout_.vertex_offset);
  auto vtx = [&](size_t i) { return int(idx_[first + i * stride + vertex_offset]); };
  const int v0 = vtx(0);
  for (size_t i = 1; i + 1 < n; ++i) {
    out.corners.push_back({v0, vtx(i), vtx(i + 1)});
    out.materials.push_back(material_);
  }
}

void ListReader::read_triangles() {
  const XMLElement* p = prim_->FirstChildElement("p");
  if (!p) {
    if (has_count_ && count_ > 0) msg_.fail(prim_, "missing <p>");
    return;
  }
  const size_t stride = size_t(layout_.stride);
  const size_t per_tri = 3 * stride;
  const size_t n = read_indices(p, has_count_ && count_ < (uint64_t(1) << 40) ? count_ * per_tri : 0);
  if (has_count_ && (n % per_tri != 0 || n / per_tri != count_))
    msg_.fail(p, "has " + std::to_string(n) + " indices; count=\"" + std::to_string(count_) + "\" with " +
                     std::to_string(stride) + " per vertex needs " + std::to_string(count_ * per_tri));
  if (n % per_tri != 0)
    msg_.fail(p, "has " + std::to_string(n) + " indices, not a multiple of " + std::to_string(per_tri) +
                     " (3 vertices of " + std::to_string(stride) + " indices)");
  check_indices(p, 0, n);
  for (size_t t = 0; t < n / per_tri; ++t) add_polygon(t * per_tri, 3);
}

// The polygon sizes of a <vcount>, each at least 3; `needed` is the number
// of indices they take.
std::vector<long long> ListReader::read_vertex_counts(const XMLElement* vc, uint64_t* needed) const {
  std::vector<long long> counts;
  std::string vbuf;
  std::string_view bad;
  if (!parse_list(element_text(vc, vbuf), counts, &bad)) msg_.fail(vc, quote(bad) + " is not a vertex count");
  if (has_count_ && counts.size() != count_)
    msg_.fail(vc, "lists " + std::to_string(counts.size()) + " polygons but count=\"" + std::to_string(count_) +
                      "\"");
  *needed = 0;
  for (size_t i = 0; i < counts.size(); ++i) {
    if (counts[i] < 3)
      msg_.fail(vc, "polygon " + std::to_string(i) + " has " + std::to_string(counts[i]) +
                        " vertices; a polygon needs at least 3");
    if (uint64_t(counts[i]) > (uint64_t(1) << 40))
      msg_.fail(vc, "polygon " + std::to_string(i) + " is impossibly large");
    *needed += uint64_t(counts[i]) * uint64_t(layout_.stride);
    if (*needed > (uint64_t(1) << 62)) msg_.fail(vc, "the polygons are impossibly large");
  }
  return counts;
}

void ListReader::read_polylist() {
  const XMLElement* vc = prim_->FirstChildElement("vcount");
  const XMLElement* p = prim_->FirstChildElement("p");
  if (!vc && !p && (!has_count_ || count_ == 0)) return;  // an empty list
  if (!vc) msg_.fail(prim_, "missing <vcount>");
  if (!p) msg_.fail(prim_, "missing <p>");
  uint64_t needed = 0;
  const std::vector<long long> counts = read_vertex_counts(vc, &needed);
  const size_t n = read_indices(p, needed);
  if (n != needed)
    msg_.fail(p, "has " + std::to_string(n) + " indices but <vcount> with " + std::to_string(layout_.stride) +
                     " per vertex needs " + std::to_string(needed));
  check_indices(p, 0, n);
  size_t first = 0;
  for (long long c : counts) {
    add_polygon(first, size_t(c));
    first += size_t(c) * size_t(layout_.stride);
  }
}

// One <p> per polygon; <ph> is a polygon with holes.
void ListReader::read_polygons() {
  const size_t stride = size_t(layout_.stride);
  uint64_t polys = 0;
  for (const XMLElement* c = prim_->FirstChildElement(); c; c = c->NextSiblingElement()) {
    const XMLElement* p = nullptr;
    if (std::strcmp(c->Name(), "p") == 0) {
      p = c;
    } else if (std::strcmp(c->Name(), "ph") == 0) {
      p = c->FirstChildElement("p");
      if (!p) msg_.fail(c, "missing <p>");
      msg_.warn(c, "holes (<h>) are not supported; the polygon is filled");
    } else {
      continue;
    }
    ++polys;
    idx_.clear();
    const size_t n = read_indices(p);
    if (n % stride != 0)
      msg_.fail(p, "has " + std::to_string(n) + " indices, not a multiple of " + std::to_string(stride) +
                       " (indices per vertex)");
    if (n / stride < 3)
      msg_.fail(p, "the polygon has " + std::to_string(n / stride) + " vertices; a polygon needs at least 3");
    check_indices(p, 0, n);
    add_polygon(0, n / stride);
  }
  if (has_count_ && polys != count_)
    msg_.fail(prim_, "holds " + std::to_string(polys) + " polygons but count=\"" + std::to_string(count_) + "\"");
}

}  // namespace

void read_primitive_list(const XMLElement* prim, const PrimitiveListContext& ctx, MeshPrimitives& mesh) {
  ListReader(prim, ctx, mesh).read();
}

void check_primitive_limit(const Messages& msg, const XMLElement* e, size_t have, size_t more) {
  if (more > kMaxScenePrimitives - std::min(have, kMaxScenePrimitives))
    msg.fail(e, "the scene would have more than " + std::to_string(kMaxScenePrimitives) +
                    " triangles and spheres, the loader's limit (is a node instanced too many times?)");
}

}  // namespace pt::collada
