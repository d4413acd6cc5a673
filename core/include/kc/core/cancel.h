#pragma once
/// The one cancellation of kcwarp's long computations.

#include <exception>

namespace kc {

/// Thrown when a progress callback asks a long computation to stop: a bind (app::BindStep), the
/// rigidity QP (RigidityQpOptions::progress returning false) and app::setRigidity, which first
/// puts the session back as it was. Whoever asked catches it; nothing else does.
class Cancelled : public std::exception {
 public:
  const char* what() const noexcept override { return "cancelled"; }
};

}  // namespace kc
