#pragma once
// A pair of the cloth's primitives for self-contact (self_contact_term.hpp), as the four vertices of
// its stencil: point-triangle (p, t0, t1, t2) or edge-edge (a0, a1, b0, b1).
#include <array>

namespace fnopt {

struct SelfContactPair {
  enum class Kind : int { PointTriangle, EdgeEdge };
  Kind kind;
  std::array<int, 4> vertices;

  bool operator<(const SelfContactPair& o) const {
    return kind != o.kind ? kind < o.kind : vertices < o.vertices;
  }
  bool operator==(const SelfContactPair& o) const { return kind == o.kind && vertices == o.vertices; }
};

}  // namespace fnopt
