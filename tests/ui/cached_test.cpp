#include "kc/ui/cached.h"

#include <gtest/gtest.h>

#include <utility>

namespace kc::ui {
namespace {

TEST(Cached, ComputesOncePerKey) {
  Cached<int, std::pair<Version, int>> c;
  Version v;
  int calls = 0;
  const auto square = [&](int x) { return [&calls, x] { return ++calls, x * x; }; };
  EXPECT_FALSE(c.current({v, 3}));
  EXPECT_EQ(c.get({v, 3}, square(3)), 9);
  EXPECT_EQ(c.get({v, 3}, square(3)), 9);
  EXPECT_EQ(calls, 1) << "the same key: no recomputation";
  EXPECT_TRUE(c.current({v, 3}));
  EXPECT_EQ(c.get({v, 4}, square(4)), 16);
  EXPECT_EQ(calls, 2) << "another input";
  v.bump();
  EXPECT_FALSE(c.current({v, 4})) << "a bumped version is a new key";
  EXPECT_EQ(c.get({v, 4}, square(4)), 16);
  EXPECT_EQ(calls, 3);
}

TEST(Cached, InvalidateRecomputesWithTheSameKey) {
  Cached<int, Version> c;
  const Version v;
  int calls = 0;
  c.get(v, [&] { return ++calls; });
  c.invalidate();
  EXPECT_FALSE(c.current(v));
  EXPECT_FALSE(c.key().has_value());
  EXPECT_EQ(c.get(v, [&] { return ++calls; }), 2);
  EXPECT_EQ(c.value(), 2);
}

TEST(Cached, AnEffectRunsOncePerKey) {
  CachedEffect<Version> upload;
  Version v;
  int uploads = 0;
  upload.get(v, [&] { ++uploads; });
  upload.get(v, [&] { ++uploads; });
  EXPECT_EQ(uploads, 1);
  v.bump();
  upload.get(v, [&] { ++uploads; });
  EXPECT_EQ(uploads, 2);
}

TEST(Version, EqualUntilBumped) {
  Version a;
  const Version b = a;
  EXPECT_EQ(a, b);
  a.bump();
  EXPECT_NE(a, b);
}

}  // namespace
}  // namespace kc::ui
