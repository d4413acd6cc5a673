#pragma once
// The recovery copy of a cage being drawn: what the GUI keeps of an unbound cage, so that a crash
// or a kill before the first bind loses nothing.
//
// File: {"version": 1, "points": [[x, y], ...], "closed": bool, "edges": [[i, j], ...],
// "image": "<the picture's path>", "image_upright": true} (the cage file's fields, file_io.h, plus
// the picture; "image_upright" as in a session: missing means the picture as stored).

#include <string>

#include "kc/core/cage.h"

namespace kc::app {

/// A cage being drawn (open, short or crossing itself are all allowed) and its picture's path.
struct DraftCage {
  Cage cage;
  std::string image;
  bool imageUpright = true;  ///< The cage was drawn on the picture turned upright (Session::imageUpright).
};

/// Writes the draft atomically (writeFileAtomic); InputError naming the file on failure.
void saveDraftCage(const std::string& path, const DraftCage& draft);

/// Reads a draft: the file's size (kMaxJsonFileBytes), its parse cost, the points (count, finite,
/// bounded) and the edges' indices are checked before anything is built, as for a cage file; the
/// cage's shape is not (a draft may be unfinished). InputError naming the file and the problem.
DraftCage loadDraftCage(const std::string& path);

}  // namespace kc::app
