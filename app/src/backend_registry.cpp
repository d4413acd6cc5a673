// The backends kcwarp knows (the built-in ones and those registered with registerBackend) and the
// generic handling of a backend's described parameters (BackendParameter).

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "backends.h"
#include "kc/app/backend.h"
#include "kc/app/text.h"

namespace kc::app {
namespace {

std::vector<const Backend*>& registry() {
  static std::vector<const Backend*> backends{&kcBackend(), &lbcBackend()};
  return backends;
}

std::string valuesKey(const Backend& backend, const BackendParameter& parameter) {
  return std::string(backend.parameterBlock()) + "." + parameter.key;
}

}  // namespace

const Backend& backendFor(std::string_view name) {
  for (const Backend* b : registry())
    if (name == b->name()) return *b;
  std::string names;
  for (const std::string_view n : backendNames()) names += (names.empty() ? "" : ", ") + std::string(n);
  throw std::invalid_argument("backend '" + std::string(name) + "' is not available (available: " + names + ")");
}

std::vector<std::string_view> backendNames() {
  std::vector<std::string_view> names;
  for (const Backend* b : registry()) names.push_back(b->name());
  return names;
}

bool registerBackend(const Backend& backend) {
  if (backend.parameterBlock().empty() && !backend.parameters().empty())
    throw std::invalid_argument("backend '" + std::string(backend.name()) + "' has parameters but no parameter block");
  for (const Backend* b : registry()) {
    if (b->name() == backend.name())
      throw std::invalid_argument("backend '" + std::string(backend.name()) + "' is registered twice");
    if (!backend.parameterBlock().empty() && b->parameterBlock() == backend.parameterBlock())
      throw std::invalid_argument("backend '" + std::string(backend.name()) + "': parameter block '" +
                                  std::string(backend.parameterBlock()) + "' is taken by '" + std::string(b->name()) + "'");
  }
  registry().push_back(&backend);
  return true;
}

double parameterValue(const Backend& backend, const BackendParameter& parameter, const BindParams& params) {
  if (parameter.get) return parameter.get(params);
  const auto it = params.values.find(valuesKey(backend, parameter));
  return it == params.values.end() ? parameter.defaultValue : it->second;
}

std::string parameterRange(const BackendParameter& parameter) {
  if (!parameter.accepts.empty()) return parameter.accepts;
  switch (parameter.type) {
    case BackendParameter::Type::Boolean:
      return "true or false";
    case BackendParameter::Type::Choice: {
      std::string list;
      for (const std::string& c : parameter.choices) list += (list.empty() ? "" : ", ") + c;
      return "one of " + list;
    }
    case BackendParameter::Type::Integer: {
      char text[64];
      std::snprintf(text, sizeof text, "an integer in [%.0f, %.0f]", parameter.min, parameter.max);
      return text;
    }
    case BackendParameter::Type::Number:
      break;
  }
  return "a number in [" + shortNumber(parameter.min) + ", " + shortNumber(parameter.max) + (parameter.openMax ? ")" : "]");
}

std::string parameterFlag(const Backend& backend, const BackendParameter& parameter) {
  const std::string block(backend.parameterBlock());
  const bool negated = parameter.type == BackendParameter::Type::Boolean && parameter.defaultValue != 0.0;
  std::string flag = "--" + std::string(negated ? "no-" : "") + (block.empty() ? "" : block + "-") + parameter.key;
  std::replace(flag.begin(), flag.end(), '_', '-');
  return flag;
}

void setParameter(const Backend& backend, const BackendParameter& parameter, BindParams& params, double value) {
  const bool whole = std::isfinite(value) && value == std::round(value);
  using Type = BackendParameter::Type;
  bool ok = false;
  switch (parameter.type) {
    case Type::Choice:
      ok = whole && value >= 0.0 && value < static_cast<double>(parameter.choices.size());
      break;
    case Type::Boolean:
      ok = value == 0.0 || value == 1.0;
      break;
    case Type::Integer:
    case Type::Number:
      ok = std::isfinite(value) && value >= parameter.min &&
           (parameter.openMax ? value < parameter.max : value <= parameter.max) && (parameter.type != Type::Integer || whole);
      break;
  }
  if (!ok) throw std::invalid_argument("must be " + parameterRange(parameter));
  if (parameter.set) parameter.set(params, value);
  else params.values[valuesKey(backend, parameter)] = value;
}

nlohmann::json parametersToJson(const Backend& backend, const BindParams& p) {
  nlohmann::json block = nlohmann::json::object();
  for (const BackendParameter& parameter : backend.parameters()) {
    if (!parameter.stored) continue;
    const double v = parameterValue(backend, parameter, p);
    switch (parameter.type) {
      case BackendParameter::Type::Boolean:
        block[parameter.key] = v != 0.0;
        break;
      case BackendParameter::Type::Choice:
        block[parameter.key] = parameterText(parameter, v);
        break;
      case BackendParameter::Type::Integer:
        block[parameter.key] = static_cast<long long>(v);
        break;
      case BackendParameter::Type::Number:
        block[parameter.key] = v;
        break;
    }
  }
  return block;
}

std::string parametersText(const Backend& backend, const BindParams& p) {
  std::string text;
  for (const BackendParameter& parameter : backend.parameters()) {
    if (!parameter.stored) continue;
    std::string name = parameter.key;
    std::replace(name.begin(), name.end(), '_', ' ');
    text += (text.empty() ? "" : ", ") + name + " " + parameterText(parameter, parameterValue(backend, parameter, p));
  }
  return text;
}

std::string parameterText(const BackendParameter& parameter, double value) {
  if (parameter.type == BackendParameter::Type::Boolean) return value != 0.0 ? "true" : "false";
  if (parameter.type == BackendParameter::Type::Choice) {
    const auto k = static_cast<std::size_t>(value);
    return value >= 0.0 && k < parameter.choices.size() ? parameter.choices[k] : "unknown";
  }
  char text[32];
  if (parameter.type == BackendParameter::Type::Integer) {
    std::snprintf(text, sizeof text, "%.0f", value);
    return text;
  }
  for (int digits = 15; digits <= 17; ++digits) {  // the shortest text that reads back as `value`
    std::snprintf(text, sizeof text, "%.*g", digits, value);
    if (std::strtod(text, nullptr) == value) break;
  }
  return text;
}

std::optional<double> parseParameter(const BackendParameter& parameter, std::string_view text) {
  if (parameter.type == BackendParameter::Type::Boolean) {
    if (text == "true") return 1.0;
    if (text == "false") return 0.0;
    return std::nullopt;
  }
  if (parameter.type == BackendParameter::Type::Choice) {
    for (std::size_t k = 0; k < parameter.choices.size(); ++k)
      if (parameter.choices[k] == text) return static_cast<double>(k);
    return std::nullopt;
  }
  const std::string s(text);
  char* end = nullptr;
  const double value = std::strtod(s.c_str(), &end);
  if (s.empty() || end != s.c_str() + s.size()) return std::nullopt;
  return value;
}

}  // namespace kc::app
