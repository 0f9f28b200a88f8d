// A mesh's <source> data (see mesh_sources.h).
#include "common/collada/mesh_sources.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <string_view>

#include "common/collada/xml_values.h"

namespace pt::collada {

// The numbers of a <float_array>, which must match its count attribute.
std::vector<double> MeshSources::read_array(const XMLElement* arr) const {
  std::string buf;
  const std::string_view s = element_text(arr, buf);
  uint64_t declared = 0;
  const bool has_count = count_attribute(msg_, arr, "count", &declared);
  std::vector<double> values;
  values.reserve(has_count ? std::min<uint64_t>(declared, max_numbers(s)) : 0);
  std::string_view bad;
  if (!parse_list(s, values, &bad)) msg_.fail(arr, quote(bad) + " is not a number");
  if (has_count && values.size() != declared)
    msg_.fail(arr, "count=\"" + std::to_string(declared) + "\" but it holds " + std::to_string(values.size()) +
                       " numbers");
  return values;
}

const PositionData& MeshSources::positions(const XMLElement* source) {
  const auto cached = cache_.find(source);
  if (cached != cache_.end()) return cached->second;

  const XMLElement* tc = source->FirstChildElement("technique_common");
  const XMLElement* acc = tc ? tc->FirstChildElement("accessor") : nullptr;
  if (!acc) msg_.fail(source, "missing <technique_common><accessor>");
  const XMLElement* arr = doc_.resolve(acc, "source", "float_array");
  const std::vector<double> values = read_array(arr);

  uint64_t count = 0, stride = 1, offset = 0;
  if (!count_attribute(msg_, acc, "count", &count)) msg_.fail(acc, "missing the count attribute");
  count_attribute(msg_, acc, "stride", &stride);
  count_attribute(msg_, acc, "offset", &offset);
  if (stride < 3) msg_.fail(acc, "positions need stride >= 3, found " + std::to_string(stride));
  if (count > 0) {
    // Overflow-safe form of offset + (count - 1) * stride + 3 <= size.
    const uint64_t n = values.size();
    if (offset > n || 3 > n - offset || (count - 1) > (n - offset - 3) / stride)
      msg_.fail(acc, "count=\"" + std::to_string(count) + "\" with stride " + std::to_string(stride) +
                         " reads past the end of " + msg_.describe(arr) + ", which holds " + std::to_string(n) +
                         " numbers");
  }

  if (count > uint64_t(std::numeric_limits<int>::max())) msg_.fail(acc, "too many positions");
  PositionData d;
  d.array = arr;
  d.xyz.resize(3 * count);
  for (uint64_t i = 0; i < count; ++i) {
    const double* p = &values[offset + i * stride];
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
      msg_.fail(arr, "position " + std::to_string(i) + " has a coordinate that is not finite (NaN or infinity)");
    d.xyz[3 * i] = p[0];
    d.xyz[3 * i + 1] = p[1];
    d.xyz[3 * i + 2] = p[2];
  }
  return cache_.emplace(source, std::move(d)).first->second;
}

const XMLElement* MeshSources::position_source(const XMLElement* input) const {
  const char* url = input->Attribute("source");
  // VERTEX normally names the mesh's <vertices>; accept a <source> as well.
  if (url && url[0] == '#') {
    const XMLElement* target = doc_.find(std::string_view(url + 1));
    if (target && std::strcmp(target->Name(), "source") == 0) return target;
  }
  const XMLElement* verts = doc_.resolve(input, "source", "vertices");
  for (const XMLElement* in = verts->FirstChildElement("input"); in; in = in->NextSiblingElement("input")) {
    const char* sem = in->Attribute("semantic");
    if (sem && std::strcmp(sem, "POSITION") == 0) return doc_.resolve(in, "source", "source");
  }
  msg_.fail(verts, "has no <input semantic=\"POSITION\">");
}

uint64_t MeshSources::element_count(const XMLElement* source) const {
  const XMLElement* tc = source->FirstChildElement("technique_common");
  const XMLElement* acc = tc ? tc->FirstChildElement("accessor") : nullptr;
  uint64_t count = 0;
  if (acc && count_attribute(msg_, acc, "count", &count)) return count;
  return std::numeric_limits<uint64_t>::max();
}

}  // namespace pt::collada
