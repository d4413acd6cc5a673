#pragma once
/// The session: everything needed to reproduce a warp (ARCHITECTURE.md, Session file).

#include <cstdint>
#include <optional>
#include <string>

#include "kc/core/cage.h"
#include "kc/core/deform.h"
#include "kc/core/kernel/interpolator.h"
#include "kc/core/types.h"
#include "kc/core/weights/heat_diffusion.h"
#include "kc/core/weights/optimizer.h"
#include "kc/sampling/sampler.h"

namespace kc::app {

/// Parameters of one bind. Defaults are what `kcwarp-cli bind` uses.
struct BindParams {
  double spacing = 6.0;    ///< h, pixels.
  double sigma = 0.0;      ///< σ in pixels; ≤ 0 = automatic (3T/π, thesis 3.28, T measured).
  InitOptions init;        ///< W0: method and diffusion iterations.
  Method method = Method::QP;
  InterpMode interp = InterpMode::Exact;
  std::string backend = "kc";
  sampling::SamplerKind sampler = sampling::SamplerKind::BlueNoise;
  double margin = -1.0;    ///< Sampling margin around the image; < 0 = automatic.
  std::uint64_t seed = 1;
};

std::string_view toString(InitMethod m);
std::string_view toString(Method m);
std::string_view toString(InterpMode m);
std::string_view toString(sampling::SamplerKind k);
/// Parsers return false on unknown names (callers report the accepted ones).
bool parseInitMethod(std::string_view s, InitMethod& m);
bool parseMethod(std::string_view s, Method& m);
bool parseInterpMode(std::string_view s, InterpMode& m);
bool parseSamplerKind(std::string_view s, sampling::SamplerKind& k);

/// The kernel-coordinate field of a bound session: w(x) for any points.
struct CoordinateField {
  KernelInterpolator interpolator;
  KernelCoefficients coefficients;

  bool ready() const { return interpolator.ok() && coefficients.U.size() > 0; }
  /// w(p) for every row of P: #P×m.
  Weights weightsAt(const Points& P) const { return interpolator.evaluate(coefficients, P); }
};

/// Seconds spent in each stage of the bind that produced a session (saved with it).
struct BindTimings {
  double sampling = 0.0, assemble = 0.0, factor = 0.0, init = 0.0, optimize = 0.0, solve = 0.0, total = 0.0;
};

struct Session {
  Cage cage;
  BindParams params;
  double sigma = 0.0;          ///< σ actually used.
  int imageWidth = 0, imageHeight = 0;
  SampleSet samples;
  Weights W0;                  ///< Initial (target) weights, #S×m.
  Weights W;                   ///< Optimized weights, #S×m.
  Pose pose;                   ///< Current pose (empty = rest).
  std::string image;           ///< Image path as written in the file (may be empty).
  BindTimings timings;         ///< How long the bind took.
  CoordinateField field;       ///< Derived from samples, σ and W; not saved.
};

}  // namespace kc::app
