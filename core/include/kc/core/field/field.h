#pragma once
/// The coordinate field: weights w(P) at any points, linear in per-node coefficients,
///   w(P) = E(P) · Coef      (E(P) #P×nodes sparse, Coef nodes×m, w #P×m).
/// The one door to weights for every consumer (eval, warp, heatmaps, stats, the GUI, the
/// conformance suite). Implementations: KernelField (kernel coordinates, thesis 1.9 / 6.2–6.3)
/// and MeshField (a triangle mesh with per-vertex weights, barycentric interpolation). A field may
/// carry a lower bound on its weights (LobeBound), applied after E·Coef by weightsAt, gradientsAt
/// and app::FieldSampler: the operators are the unbounded field's.

#include <memory>
#include <span>
#include <string_view>
#include <vector>

#include "kc/core/field/lobe_bound.h"
#include "kc/core/kernel/kernel_matrix.h"
#include "kc/core/types.h"

namespace kc {

/// Where a field is defined: everywhere (kernel coordinates) or only on its mesh.
enum class FieldDomain { Plane, Mesh };

class CoordinateField {
 public:
  virtual ~CoordinateField() = default;

  /// m: the number of controls (columns of w).
  virtual Index controls() const = 0;
  /// The number of nodes (rows of Coef).
  virtual Index nodes() const = 0;
  /// True when the field can be evaluated (computed and holding coefficients).
  virtual bool ready() const = 0;

  /// E(P): #P×nodes sparse evaluation operator, w(P) = E(P)·Coef. A point outside the domain
  /// has an empty row (its weights are 0). Throws std::invalid_argument for non-finite P.
  virtual SparseRowMatrix evaluationOperator(const Points& P) const = 0;
  /// ∂E/∂x and ∂E/∂y at P (#P×nodes each): ∇w(P) = (∂E/∂x·Coef, ∂E/∂y·Coef).
  virtual void gradientOperators(const Points& P, SparseRowMatrix& Ex, SparseRowMatrix& Ey) const = 0;
  /// Columns `columns` of Coef (all when empty): nodes×#columns (a copy).
  virtual RowMatrix coefficientColumns(std::span<const Index> columns = {}) const = 0;

  /// Which kind of domain the field has.
  virtual FieldDomain domain() const = 0;
  /// The field's kind, as a session file's `field.kind` names it ("kernel", "mesh").
  virtual std::string_view kind() const = 0;
  /// Frees memory that only update() needs (a factorization); the field evaluates as before and
  /// update() rebuilds it. Default: nothing to free.
  virtual void releaseWorkspace() {}
  /// True when p lies in the domain (always for FieldDomain::Plane).
  virtual bool contains(const Vec2& p) const = 0;

  /// Updates the coefficients after the data weights W changed in `columns` (all when empty).
  /// W holds one row per data point of the field (kernel: the samples, #S×m; mesh: the
  /// vertices, #V×m). The other columns are kept.
  virtual void update(const Weights& W, std::span<const Index> columns = {}) = 0;

  /// w(P) = E(P)·Coef: #P×m, then the lobe bound when set.
  virtual Weights weightsAt(const Points& P) const;
  /// ∇w at P: two #P×m matrices, ∂w/∂x = ∂E/∂x·Coef and ∂w/∂y = ∂E/∂y·Coef (of the bounded field
  /// when a lobe bound is set: LobeBound::applyGradients).
  virtual void gradientsAt(const Points& P, Weights& dWdx, Weights& dWdy) const;

  /// The lower bound every evaluation applies (lobe_bound.h); null: none. Its cage's points must be
  /// the field's controls.
  void setLobeBound(std::shared_ptr<const LobeBound> bound) { m_bound = std::move(bound); }
  const LobeBound* lobeBound() const { return m_bound.get(); }
  std::shared_ptr<const LobeBound> sharedLobeBound() const { return m_bound; }

  /// Coef: nodes×m.
  RowMatrix coefficients() const { return coefficientColumns({}); }
  /// Writes columns `columns` (all when empty) of E·Coef into W (#P×m; E #P×nodes). Other
  /// columns of W are left as they are. Each row is summed in E's storage order on its own, so
  /// any thread count gives the same bits.
  void apply(const SparseRowMatrix& E, std::span<const Index> columns, Weights& W) const;

 protected:
  /// The bound's part of gradientsAt: dWdx, dWdy of the unbounded field at P become the bounded
  /// field's, `unbounded(P)` giving the unbounded weights there (nothing without a bound).
  template <class Unbounded>
  void boundGradients(const Points& P, Weights& dWdx, Weights& dWdy, Unbounded&& unbounded) const {
    if (m_bound) m_bound->applyGradients(P, unbounded(P), dWdx, dWdy);
  }

  std::shared_ptr<const LobeBound> m_bound;
};

namespace detail {
/// `columns` checked against m (std::invalid_argument when one is out of range), or 0..m−1 when empty.
std::vector<Index> fieldColumns(std::span<const Index> columns, Index m);
}  // namespace detail

}  // namespace kc
