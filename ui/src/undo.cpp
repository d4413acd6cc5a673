#include "kc/ui/undo.h"

#include <cassert>

namespace kc::ui {

void UndoStack::push(UndoEntry entry) {
  m_redo.clear();
  m_undo.push_back(std::move(entry));
  if (m_undo.size() > limit) m_undo.erase(m_undo.begin());
}

UndoEntry& UndoStack::popUndo() {
  assert(canUndo());
  m_redo.push_back(std::move(m_undo.back()));
  m_undo.pop_back();
  return m_redo.back();
}

UndoEntry& UndoStack::popRedo() {
  assert(canRedo());
  m_undo.push_back(std::move(m_redo.back()));
  m_redo.pop_back();
  return m_undo.back();
}

void UndoStack::clear() {
  m_undo.clear();
  m_redo.clear();
}

Weights gatherRows(const Weights& W, const std::vector<Index>& rows) {
  if (rows.empty()) return W;
  Weights R(static_cast<Index>(rows.size()), W.cols());
  for (std::size_t k = 0; k < rows.size(); ++k) R.row(static_cast<Index>(k)) = W.row(rows[k]);
  return R;
}

void scatterRows(Weights& W, const std::vector<Index>& rows, const Weights& R) {
  if (rows.empty()) {
    W = R;
    return;
  }
  for (std::size_t k = 0; k < rows.size(); ++k) W.row(rows[k]) = R.row(static_cast<Index>(k));
}

}  // namespace kc::ui
