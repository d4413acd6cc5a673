// Which parts of a vertex buffer the renderer sends again (buffer_updates.h).
#include <gtest/gtest.h>

#include <vector>

#include "kc/ui/buffer_updates.h"

namespace kc::ui {
namespace {

std::vector<ElementRun> runs(const std::vector<float>& a, const std::vector<float>& b, std::size_t gap) {
  return changedRuns(a.data(), b.data(), a.size(), sizeof(float), gap);
}

TEST(ChangedRuns, NothingChangedSendsNothing) {
  const std::vector<float> a = {1, 2, 3, 4};
  EXPECT_TRUE(runs(a, a, 4).empty());
}

TEST(ChangedRuns, SeparateChangesAreSeparateRunsCloseOnesMerge) {
  std::vector<float> a(100, 0.0f), b = a;
  b[3] = b[4] = 1.0f;
  b[10] = 1.0f;
  b[90] = 1.0f;
  EXPECT_EQ(runs(a, b, 1), (std::vector<ElementRun>{{3, 5}, {10, 11}, {90, 91}}));
  EXPECT_EQ(runs(a, b, 8), (std::vector<ElementRun>{{3, 11}, {90, 91}}));  // 5 equal elements between: merged
  EXPECT_EQ(runElements(runs(a, b, 8)), 9u);
}

TEST(ChangedRuns, ComparesWholeElements) {
  struct Colour {
    unsigned char r, g, b, a;
  };
  std::vector<Colour> a(6, Colour{1, 2, 3, 4}), b = a;
  b[2].a = 5;  // one byte of element 2
  EXPECT_EQ(changedRuns(a.data(), b.data(), a.size(), sizeof(Colour), 1), (std::vector<ElementRun>{{2, 3}}));
}

}  // namespace
}  // namespace kc::ui
