// A mesh's <source> data as the primitive readers need it: the positions a
// VERTEX input refers to (read once per <source>, however often the mesh is
// instanced) and the element counts of other sources, for index checks.
#pragma once
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "common/collada/document.h"
#include "common/collada/messages.h"

namespace pt::collada {

struct PositionData {
  const XMLElement* array = nullptr;  // the <float_array>, for messages
  std::vector<double> xyz;            // 3 per position, in the file's space
  size_t count() const { return xyz.size() / 3; }
};

class MeshSources {
 public:
  MeshSources(const Messages& msg, const Document& doc) : msg_(msg), doc_(doc) {}

  // Positions of a <source>: its accessor's first three parameters, all
  // finite. Cached per <source>.
  const PositionData& positions(const XMLElement* source);

  // The <source> holding the positions a VERTEX input refers to.
  const XMLElement* position_source(const XMLElement* vertex_input) const;

  // Number of elements of a non-position <source> (for index checks);
  // UINT64_MAX when it cannot be told.
  uint64_t element_count(const XMLElement* source) const;

 private:
  std::vector<double> read_array(const XMLElement* array) const;

  const Messages& msg_;
  const Document& doc_;
  std::unordered_map<const XMLElement*, PositionData> cache_;
};

}  // namespace pt::collada
