#pragma once
// Private to kc::app: the backend instances behind backendFor().

#include "kc/app/backend.h"

namespace kc::app {

/// Kernel coordinates (kc_backend.cpp).
const Backend& kcBackend();
/// Local barycentric coordinates on a mesh of the cage interior (lbc_backend.cpp).
const Backend& lbcBackend();

}  // namespace kc::app
