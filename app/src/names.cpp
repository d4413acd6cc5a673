#include <array>
#include <utility>

#include "kc/app/session.h"

namespace kc::app {
namespace {

template <class E, std::size_t N>
std::string_view nameOf(const std::array<std::pair<E, std::string_view>, N>& table, E value) {
  for (const auto& [e, name] : table)
    if (e == value) return name;
  return "unknown";
}

template <class E, std::size_t N>
bool parseName(const std::array<std::pair<E, std::string_view>, N>& table, std::string_view s, E& value) {
  for (const auto& [e, name] : table)
    if (name == s) {
      value = e;
      return true;
    }
  return false;
}

constexpr std::array<std::pair<InitMethod, std::string_view>, 4> kInit{{{InitMethod::HeatLinear, "heat-linear"},
                                                                       {InitMethod::HeatImpulse, "heat-impulse"},
                                                                       {InitMethod::InverseDistance, "inverse-distance"},
                                                                       {InitMethod::Lbc, "lbc"}}};
constexpr std::array<std::pair<Method, std::string_view>, 3> kMethod{
    {{Method::QP, "qp"}, {Method::QEC, "qec"}, {Method::L1, "l1"}}};
constexpr std::array<std::pair<InterpMode, std::string_view>, 2> kInterp{
    {{InterpMode::Exact, "exact"}, {InterpMode::Thesis, "thesis"}}};
constexpr std::array<std::pair<sampling::SamplerKind, std::string_view>, 2> kSampler{
    {{sampling::SamplerKind::BlueNoise, "blue-noise"}, {sampling::SamplerKind::Grid, "grid"}}};

constexpr std::array<std::pair<LbcTau, std::string_view>, 4> kTau{
    {{LbcTau::Square, "square"}, {LbcTau::Constant, "const"}, {LbcTau::Linear, "linear"}, {LbcTau::Sqrt, "sqrt"}}};

}  // namespace

std::string_view toString(InitMethod m) { return nameOf(kInit, m); }
std::string_view toString(Method m) { return nameOf(kMethod, m); }
std::string_view toString(InterpMode m) { return nameOf(kInterp, m); }
std::string_view toString(sampling::SamplerKind k) { return nameOf(kSampler, k); }
bool parseInitMethod(std::string_view s, InitMethod& m) { return parseName(kInit, s, m); }
bool parseMethod(std::string_view s, Method& m) { return parseName(kMethod, s, m); }
bool parseInterpMode(std::string_view s, InterpMode& m) { return parseName(kInterp, s, m); }
bool parseSamplerKind(std::string_view s, sampling::SamplerKind& k) { return parseName(kSampler, s, k); }
std::string_view toString(LbcTau t) { return nameOf(kTau, t); }
bool parseLbcTau(std::string_view s, LbcTau& t) { return parseName(kTau, s, t); }

}  // namespace kc::app
