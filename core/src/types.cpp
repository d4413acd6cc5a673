#include "kc/core/types.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace kc {

void SampleSet::validate(Index m) const {
  const Index n = X.rows();
  if (static_cast<Index>(kind.size()) != n)
    throw std::invalid_argument("samples: " + std::to_string(n) + " points but " + std::to_string(kind.size()) + " kinds");
  if (edge.rows() != n)
    throw std::invalid_argument("samples: " + std::to_string(n) + " points but " + std::to_string(edge.rows()) + " edge rows");
  if (n < m) throw std::invalid_argument("samples: fewer samples than control points");
  if (!X.allFinite()) throw std::invalid_argument("samples: non-finite coordinate");
  for (Index i = 0; i < n; ++i) {
    const SampleKind k = kind[static_cast<std::size_t>(i)];
    if ((i < m) != (k == SampleKind::Control))
      throw std::invalid_argument("samples: the first " + std::to_string(m) +
                                  " samples must be exactly the control points (sample " + std::to_string(i) + ")");
    if (k == SampleKind::Edge) {
      const int a = edge(i, 0), b = edge(i, 1);
      if (a < 0 || b < 0 || a >= m || b >= m || a == b)
        throw std::invalid_argument("samples: edge sample " + std::to_string(i) + " names no valid cage edge");
    }
  }
  for (std::size_t l = 0; l < lines.size(); ++l) {
    if (lines[l].size() < 2) throw std::invalid_argument("samples: line " + std::to_string(l) + " has fewer than two samples");
    for (std::size_t k = 0; k < lines[l].size(); ++k) {
      const Index i = lines[l][k];
      // A line's end may be the boundary sample where it meets the cage (a control or an edge sample).
      const bool end = k == 0 || k + 1 == lines[l].size();
      if (i < 0 || i >= n || (kind[static_cast<std::size_t>(i)] != SampleKind::Line &&
                              !(end && (kind[static_cast<std::size_t>(i)] == SampleKind::Edge || i < m))))
        throw std::invalid_argument("samples: line " + std::to_string(l) + " names sample " + std::to_string(i) +
                                    ", which is not a line sample" + (end ? " or a sample on the cage" : ""));
    }
  }
}

}  // namespace kc
