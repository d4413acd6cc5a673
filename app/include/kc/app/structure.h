#pragma once
/// Structure files (`--structure S.json`, ARCHITECTURE.md "Structure"): the lines kept straight
/// and parallel (thesis 5.3) and, later, rigid regions (5.4).

#include <string>
#include <vector>

#include "kc/core/cage.h"
#include "kc/core/structure/lines.h"

namespace kc::app {

/// What a structure file holds: lines (StructureLine::group indexes `groups`, the names of the
/// parallel groups in order of first appearance).
struct Structure {
  std::vector<StructureLine> lines;
  std::vector<std::string> groups;
  bool empty() const { return lines.empty(); }
};

/// Parses a structure file's text. InputError naming `where` and the entry for malformed JSON,
/// an unknown version, a line without exactly two finite points, a non-string `parallel`, or a
/// non-empty `rigid` array (rigid regions are not supported yet). Geometry against a cage is
/// checked by checkStructure.
Structure structureFromJson(const std::string& text, const std::string& where);
/// Reads and parses a structure file (file size limit as for cages).
Structure loadStructure(const std::string& path);
/// Checks the lines against the cage at spacing h (kc::validateLines: inside the cage, not
/// crossing a cage edge or each other, at least kMinLineSpacings·h long, groups of ≥ 2 parallel
/// lines); InputError "<where>: lines[k]: ..." otherwise.
void checkStructure(const Structure& structure, const Cage& cage, double h, const std::string& where);

}  // namespace kc::app
