// The solve vocabulary's progress estimate (core/solve.h).
#include "kc/core/solve.h"

#include <gtest/gtest.h>

namespace kc {
namespace {

TEST(LogProgress, HalfwayInLogScaleAndClampedAtTheEnds) {
  EXPECT_NEAR(logProgress(1e-2, 1.0, 1e-4), 0.5, 1e-12);  // two of four decades
  EXPECT_NEAR(logProgress(0.3, 3.0, 0.003), 1.0 / 3.0, 1e-12);
  EXPECT_EQ(logProgress(1e-4, 1.0, 1e-4), 1.0);  // reached
  EXPECT_EQ(logProgress(0.0, 1.0, 1e-4), 1.0);
  EXPECT_EQ(logProgress(5.0, 1.0, 1e-4), 0.0);  // above the start
  EXPECT_EQ(logProgress(2.0, 1.0, 1.0), 0.0);   // a target at the start: not reached yet
}

}  // namespace
}  // namespace kc
