#pragma once
/// Undo/redo history of the document: cage edits, pose changes, weight edits (paint strokes,
/// method switches), line edits, rigidity strokes and re-binds. Entries store what restores the state bit for bit: exact before/after
/// values, or for a method switch the two methods.

#include <algorithm>
#include <memory>
#include <string>
#include <variant>
#include <vector>

#include "kc/app/structure.h"
#include "kc/core/cage.h"
#include "kc/core/deform.h"
#include "kc/core/types.h"
#include "kc/core/weights/optimizer.h"

namespace kc::ui {

/// The pose before and after a drag, rotation or reset.
struct PoseEdit {
  Pose before, after;
};

/// The draft cage before and after a cage-tool edit.
struct CageEdit {
  Cage before, after;
};

/// Rows of W0 (targets) and W (optimized) before and after a paint stroke.
/// `rows` lists the painted samples (#R), whose targets W0Before/W0After (#R×m) hold;
/// `weightRows` the samples whose optimized weights the stroke changed (#Q: the painted ones and
/// those derived from them, e.g. the exterior rows continued from the inside, the samples near a
/// structure line), whose weights WBefore/WAfter (#Q×m) hold. Empty `rows` = all samples.
struct WeightEdit {
  std::vector<Index> rows, weightRows;
  Weights W0Before, W0After, WBefore, WAfter;
  Method methodBefore = Method::QP, methodAfter = Method::QP;
};

/// A method switch: W is re-optimized from the unchanged W0, so the two methods are all that undo
/// and redo need (the optimizer is deterministic and reads only W0: the same bits come back).
/// Only when the weights before the switch did not come from this optimizer (a session file
/// written by another version) are they kept, in WBefore (#S×m; empty otherwise).
struct MethodEdit {
  Method before = Method::QP, after = Method::QP;
  Weights WBefore;
};

/// The structure lines (kept straight / parallel, thesis 5.3) before and after a line-tool edit.
/// Applying either side re-binds a bound session with those lines.
struct LinesEdit {
  app::Structure before, after;
};

/// A rigidity-brush stroke (or Clear rigidity): the per-sample rigidity ρ (#S each) before and
/// after, and the rows of W that app::setRigidity changed (#R indices, `WBefore` / `WAfter` #R×m)
/// with the controls whose columns changed. Undo and redo write these back bit for bit and
/// re-solve only those field columns (no QP).
struct RigidityEdit {
  std::vector<double> before, after;
  std::vector<Index> rows, columns;
  Weights WBefore, WAfter;
};

/// A bound document as a bind left it: the session with its display mesh and pose (jobs.h).
struct BoundDocument;

/// A bind that replaced a bound session (Bind again, another backend, Move everything): `other`
/// holds the document on the other side of it, the previous one while the bind is done. Undo and
/// redo swap it with the present one, without binding; the edits before the bind apply to the
/// previous session again once it is back.
struct BindEdit {
  std::shared_ptr<BoundDocument> other;
};

using Edit = std::variant<PoseEdit, CageEdit, WeightEdit, MethodEdit, LinesEdit, RigidityEdit, BindEdit>;

struct UndoEntry {
  std::string label;  ///< Shown in the Edit menu, e.g. "paint w3".
  Edit edit;
};

/// Two stacks; push() clears the redo stack.
class UndoStack {
 public:
  void push(UndoEntry entry);
  bool canUndo() const { return !m_undo.empty(); }
  bool canRedo() const { return !m_redo.empty(); }
  const UndoEntry* nextUndo() const { return m_undo.empty() ? nullptr : &m_undo.back(); }
  const UndoEntry* nextRedo() const { return m_redo.empty() ? nullptr : &m_redo.back(); }
  /// Moves the newest entry to the redo stack and returns it (call only when canUndo()).
  UndoEntry& popUndo();
  /// Moves the newest redo entry back to the undo stack and returns it (only when canRedo()).
  UndoEntry& popRedo();
  void clear();
  /// Drops the entries (undo and redo) for which `drop` is true, keeping the others in order.
  template <class Pred>
  std::size_t removeIf(Pred drop) {
    std::size_t n = 0;
    for (auto* v : {&m_undo, &m_redo})
      for (auto it = v->begin(); it != v->end();)
        if (drop(*it)) it = v->erase(it), ++n;
        else ++it;
    return n;
  }
  /// Whether an entry (undo or redo) satisfies `pred`.
  template <class Pred>
  bool any(Pred pred) const {
    for (const auto* v : {&m_undo, &m_redo})
      for (const UndoEntry& e : *v)
        if (pred(e)) return true;
    return false;
  }
  /// Drops the `count` oldest undo entries.
  void dropOldest(std::size_t count) { m_undo.erase(m_undo.begin(), m_undo.begin() + static_cast<long>(std::min(count, m_undo.size()))); }
  /// The undo entries, oldest first.
  const std::vector<UndoEntry>& undoEntries() const { return m_undo; }
  std::size_t undoCount() const { return m_undo.size(); }
  std::size_t redoCount() const { return m_redo.size(); }

  /// At most this many entries are kept (oldest dropped first).
  std::size_t limit = 200;

 private:
  std::vector<UndoEntry> m_undo, m_redo;
};

/// Copies rows `rows` of W (all when empty) into a #R×m matrix.
Weights gatherRows(const Weights& W, const std::vector<Index>& rows);
/// Writes R (#R×m) into rows `rows` of W (all of W when rows is empty).
void scatterRows(Weights& W, const std::vector<Index>& rows, const Weights& R);

}  // namespace kc::ui
