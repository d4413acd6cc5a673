#pragma once
/// Weight backends: how a bind turns (cage, image size, parameters) into a coordinate field, and
/// what the result can do afterwards (BackendCapabilities, sessionCapabilities). docs/ARCHITECTURE.md,
/// "Backends", lists where code still compares a backend's name.

#include <exception>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "kc/core/names.h"
#include "kc/core/solve.h"
#include "kc/app/session.h"

namespace kc::app {

/// Announces a bind stage (name, fraction in [0, 1]); throws kc::Cancelled when asked to stop.
using BindStep = std::function<void(const char* stage, double fraction)>;

/// What a backend's sessions can do. A missing capability comes with the reason the GUI shows.
struct BackendCapabilities {
  bool targets = false;      ///< Per-sample target weights W0 exist (weights.initial).
  bool methods = false;      ///< The per-sample optimization method can be switched after a bind.
  bool painting = false;     ///< The brush paints targets and re-optimizes the painted samples.
  bool outsideCage = false;  ///< The field has weights outside the cage (`--outside deform`).
  bool lines = false;        ///< Structure lines kept straight and parallel (`--structure` "lines", thesis 5.3).
  bool rigidity = false;     ///< Rigid regions (`--structure` "rigid", the rigidity brush; thesis 5.4).
  std::string why;           ///< Why the missing capabilities are missing (tooltip text).
};

/// One bind parameter of a backend, described once: `kcwarp-cli bind`'s flag, the session file's
/// key and the Bind panel's widget are made from it (backend_registry.cpp, session_io.cpp,
/// cli_bind.cpp, bind_panel.cpp).
struct BackendParameter {
  enum class Type {
    Number,   ///< A real number in [min, max] (or [min, max) with openMax).
    Integer,  ///< An integer in [min, max].
    Choice,   ///< One of `choices`, by name; the value is its index.
    Boolean,  ///< 0 or 1: true/false in the session; the flag --<key> (--no-<key> when true by default) turns the default over.
  };
  /// Where the Bind panel draws the parameter.
  enum class Panel {
    Shown,     ///< Among the backend's parameters.
    Advanced,  ///< Under the collapsed "Advanced" header.
    Hidden,    ///< Not in the Bind panel (set elsewhere in the GUI, or by another parameter's widget).
  };
  /// The key in the session's params.<block> (at the top of params for a backend without a
  /// block) and the flag --<block>-<key> (--<key> without a block), '_' written as '-'.
  std::string key;
  std::string label;    ///< The Bind panel's label.
  std::string help;     ///< The CLI's help text (a Boolean's: what its flag does).
  std::string tooltip;  ///< The Bind panel's tooltip (plain words).
  Type type = Type::Number;
  double min = 0.0, max = 0.0;       ///< The accepted range (Number, Integer), inclusive.
  bool openMax = false;              ///< Number: max itself is not accepted.
  bool logarithmic = false;          ///< The panel's slider is logarithmic (Number).
  std::vector<std::string> choices;  ///< Choice: the names, written and parsed as such.
  /// What the value must be, in words, when "a number in [min, max]" (parameterRange) says it
  /// badly: "0 (off) or a positive number of spacings".
  std::string accepts;
  double defaultValue = 0.0;  ///< What BindParams{} holds.
  /// What a session file without the key means (files written before the parameter existed);
  /// none: the default.
  std::optional<double> absentValue;
  bool flag = true;    ///< `kcwarp-cli bind` has a flag for it.
  bool stored = true;  ///< The session file keeps it under its key; false: Backend::writeParameters does.
  Panel panel = Panel::Shown;
  /// Drawn in the Bind panel only when this holds (null: always), e.g. a diffusion's iterations
  /// only with a diffusion initialization.
  std::function<bool(const BindParams&)> shownWhen;
  /// A widget of the GUI's own instead of the type's ("" = the type's): "kernel-width" (an Auto
  /// checkbox for the value 0, the width the bind will use shown beside it) and "local-targets"
  /// (a Boolean switch with the locality length it gives, in pixels).
  std::string widget;
  /// Where the value lives in BindParams (a backend's own struct); when empty, in
  /// BindParams::values under "<block>.<key>".
  std::function<double(const BindParams&)> get;
  std::function<void(BindParams&, double)> set;
};

/// Makes `parameter` a Choice over the named enum E (kc/core/names.h: its names, in table order)
/// kept where `get` reads and `set` writes it, `defaultValue` being BindParams{}'s.
template <NamedEnum E, class Get, class Set>
void describeChoice(BackendParameter& parameter, E defaultValue, Get get, Set set) {
  static constexpr auto index = [](E e) {
    for (std::size_t k = 0; k < EnumNames<E>::table.size(); ++k)
      if (EnumNames<E>::table[k].first == e) return static_cast<double>(k);
    return 0.0;
  };
  parameter.type = BackendParameter::Type::Choice;
  parameter.choices.clear();
  for (const auto& [value, name] : EnumNames<E>::table) parameter.choices.emplace_back(name);
  parameter.defaultValue = index(defaultValue);
  parameter.get = [get](const BindParams& p) { return index(get(p)); };
  parameter.set = [set](BindParams& p, double v) { set(p, EnumNames<E>::table[static_cast<std::size_t>(v)].first); };
}

class Backend {
 public:
  virtual ~Backend() = default;
  /// The name in params.backend and `--backend`.
  virtual std::string_view name() const = 0;
  virtual BackendCapabilities capabilities() const = 0;
  /// The name of the GUI's backend switch ("KC", "LBC").
  virtual std::string_view displayName() const = 0;
  /// What it computes, for `kcwarp-cli bind --help` and the GUI's tooltip (one sentence, no period).
  virtual std::string_view description() const = 0;
  /// The GUI's tooltip of the backend switch (plain words).
  virtual std::string_view tooltip() const { return description(); }
  /// The name of the parameters' block: the session's params.<block>, the CLI's --<block>-* flags;
  /// "" when the backend describes no parameters.
  virtual std::string_view parameterBlock() const { return {}; }
  /// The backend's own bind parameters (the ones every backend shares are BindParams' fields):
  /// built once and kept (the Bind panel reads them every frame).
  virtual const std::vector<BackendParameter>& parameters() const {
    static const std::vector<BackendParameter> none;
    return none;
  }
  /// Writes the parameters that are not `stored` into the session's params object (keys shared by
  /// several parameters, or holding more than one) and reads them back; the described ones are
  /// read before. Throws InputError(where, …) for a value the file must not hold. Default: none.
  virtual void writeParameters(const Session&, nlohmann::json& /*params*/) const {}
  virtual void readParameters(const nlohmann::json& /*params*/, Session&, const std::string& /*where*/) const {}
  /// The backend whose parameters also shape a bind with `params` (its targets come from that
  /// backend's solver: the kc backend with LBC initialization), which the Bind panel shows under
  /// Initialization; null (the default) when none.
  virtual const Backend* targetsBackend(const BindParams&) const { return nullptr; }
  /// The spacing of the weights' detail a bind with `params` gives, which the warp mesh follows
  /// (app::weightSpacing). Default: params.spacing.
  virtual double weightSpacing(const BindParams& params) const { return params.spacing; }
  /// A warning that the cage has a place narrower than a bind with `params` resolves ("" when
  /// none, the default): `kcwarp-cli bind` prints it, the GUI shows it.
  virtual std::string narrowPlaceWarning(const Cage&, const BindParams&) const { return {}; }
  /// Fills everything of `s` a bind computes: samples, σ, W0 (when the backend has targets), W, the
  /// field and s.report (its stages' reports and times but timings.total, and the backend's own
  /// report). s.cage, s.params and the image size are set; `step` reports progress (and throws
  /// kc::Cancelled). Throws std::invalid_argument for parameters the backend rejects.
  virtual void bind(Session& s, const BindStep& step) const = 0;
  /// The backend's own report from the session's `reports.<parameterBlock()>` object (as
  /// BackendReport::toJson wrote it); null (the default) for a backend without one.
  virtual std::shared_ptr<const BackendReport> readReport(const nlohmann::json&) const { return nullptr; }
  /// Rebuilds s.field from what a session file holds (samples, W, params, the field block already
  /// parsed into s.field when it was self-contained). Throws InputError-worthy
  /// std::invalid_argument with the reason when the field cannot be rebuilt.
  virtual void rebuildField(Session& s) const = 0;
  /// Re-optimizes rows `subset` of s.W (all when empty) from s.W0 with `method` and updates the
  /// field's changed columns (returned in changedColumns). Only for backends with `methods`.
  virtual OptimizeReport reoptimize(Session& s, Method method, std::span<const Index> subset,
                                    std::vector<Index>* changedColumns) const = 0;
};

/// The backend called `name`; throws std::invalid_argument naming the available ones.
const Backend& backendFor(std::string_view name);
/// Names of every available backend: "kc", "lbc", then the registered ones in registration order.
std::vector<std::string_view> backendNames();
/// Makes `backend` available under its name to the CLI, the session files and the GUI (a static
/// object of the caller's, alive until exit). Returns true, so that one line at namespace scope
/// registers a backend:  const bool registered = kc::app::registerBackend(theBackend());
/// Throws std::invalid_argument when the name or the parameter block is taken, or when a backend
/// with parameters has no block (only the built-in kc backend keeps its keys at the top).
bool registerBackend(const Backend& backend);
/// The value of `backend`'s `parameter` in `params` (its default when BindParams::values lacks it).
double parameterValue(const Backend& backend, const BackendParameter& parameter, const BindParams& params);
/// Sets `backend`'s `parameter` in `params` to `value`; throws std::invalid_argument ("must be
/// <parameterRange>") and sets nothing when the value is not one the parameter accepts.
void setParameter(const Backend& backend, const BackendParameter& parameter, BindParams& params, double value);
/// What `parameter` accepts, in words: "a number in [1e-12, 1]", "an integer in [1, 20]", "one of
/// square, const".
std::string parameterRange(const BackendParameter& parameter);
/// `kcwarp-cli bind`'s flag for `backend`'s `parameter`: --<block>-<key>, --<key> without a block,
/// '_' as '-'; a Boolean's is --no-<key> when it is true by default.
std::string parameterFlag(const Backend& backend, const BackendParameter& parameter);
/// The value `parameter` has in text (a choice's name, "true"/"false", a number as written), and
/// back (nullopt: not a value of its type; the range is checked by setParameter).
std::string parameterText(const BackendParameter& parameter, double value);
std::optional<double> parseParameter(const BackendParameter& parameter, std::string_view text);
/// `backend`'s stored parameters in `params` as the session's params.<block> object (a choice by
/// name, a Boolean as true/false).
nlohmann::json parametersToJson(const Backend& backend, const BindParams& params);
/// The same in words for a summary line: "tau square, tolerance 0.001, max iterations 20000"; ""
/// for a backend without stored parameters.
std::string parametersText(const Backend& backend, const BindParams& params);

/// Capabilities of a bound session: its backend's, less what the session lacks (no
/// weights.initial → no targets, painting or method switches).
BackendCapabilities sessionCapabilities(const Session& s);
/// What of `structure` a backend with `caps` cannot keep: "lines", "rigid regions", "lines and rigid
/// regions", or "" when it keeps all of it. `paintedRigidity`: rigid parts held besides the
/// structure's regions (the GUI's rigidity brush) count as rigid regions.
std::string unsupportedStructure(const Structure& structure, const BackendCapabilities& caps, bool paintedRigidity = false);
/// `structure` without what a backend with `caps` cannot keep (its lines and groups, its rigid regions).
Structure keptStructure(Structure structure, const BackendCapabilities& caps);
/// The refusal of `structure` by `backend` ("lines are not supported by the 'lbc' backend (use
/// --backend kc)"), or "" when the backend keeps all of it.
std::string structureRefusal(const Structure& structure, const Backend& backend);

}  // namespace kc::app
