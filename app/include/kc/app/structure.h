#pragma once
/// Structure files (`--structure S.json`, docs/ARCHITECTURE.md "File formats"): the lines kept straight
/// and parallel (thesis 5.3) and the rigid regions (5.4, docs/rigidity.md).

#include <string>
#include <vector>

#include "kc/core/cage.h"
#include "kc/core/structure/lines.h"
#include "kc/core/structure/rigidity.h"

namespace kc::app {

/// What a structure file holds: lines (StructureLine::group indexes `groups`, the names of the
/// parallel groups in order of first appearance) and rigid regions (polygon + strength).
struct Structure {
  std::vector<StructureLine> lines;
  std::vector<std::string> groups;
  std::vector<RigidRegion> rigid;
  bool empty() const { return lines.empty() && rigid.empty(); }
};

/// Parses a structure file's text. InputError naming `where` and the entry for malformed JSON,
/// an unknown version, a line without exactly two finite points, a non-string `parallel`, a rigid
/// entry without a `polygon` of ≥ 3 finite points or with a `strength` that is not a number in
/// [0, 1] (default 1). Geometry against a cage is checked by checkStructure.
Structure structureFromJson(const std::string& text, const std::string& where);
/// A structure file's text (the lines with their parallel groups, the rigid regions); structureFromJson
/// reads it back.
std::string structureToJson(const Structure& structure);
/// Reads and parses a structure file (file size limit as for cages).
Structure loadStructure(const std::string& path);
/// Checks the lines against the cage at spacing h (kc::validateLines: inside the cage, not
/// crossing a cage edge or each other, at least kMinLineSpacings·h long, groups of ≥ 2 parallel
/// lines) and the rigid regions (kc::validateRigidRegions: inside the cage, not crossing a cage
/// edge, not self-intersecting); InputError "<where>: lines[k]: ..." / "<where>: rigid[k]: ..." otherwise.
/// `graded`: the checks of a graded bind (validateLines: no distance or length limits).
void checkStructure(const Structure& structure, const Cage& cage, double h, const std::string& where, bool graded = false);

}  // namespace kc::app
