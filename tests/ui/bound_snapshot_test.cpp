// The snapshot of a bound session the GUI draws from (makeBoundSnapshot): what it copies, and the
// samples' spacings taken over from the snapshot before a job only while the samples are the same.

#include <gtest/gtest.h>

#include <string>

#include "kc/app/file_io.h"
#include "kc/app/pipeline.h"
#include "kc/ui/bound_snapshot.h"

namespace kc::ui {
namespace {

app::Session boundStarFor(std::uint64_t seed) {
  app::BindParams p;
  p.seed = seed;
  return app::bind(app::loadCage(std::string(KC_SOURCE_DIR) + "/images/star.cage.json"), 320, 320, p);
}

TEST(BoundSnapshot, CopiesWhatTheWindowShowsOfTheSession) {
  const app::Session s = boundStarFor(1);
  const auto b = makeBoundSnapshot(s);
  EXPECT_EQ(b->cage.C, s.cage.C);
  EXPECT_EQ(b->samples.X, s.samples.X);
  EXPECT_EQ(b->spacing, s.params.spacing);
  EXPECT_EQ(b->sigma, s.sigma);
  EXPECT_EQ(b->method, s.params.kc.method);
  EXPECT_EQ(b->report.summary(), s.report.summary());
  ASSERT_EQ(b->sampleSpacing.size(), s.samples.size());
  const Eigen::VectorXd h = s.sizing ? s.sizing->at(s.samples.X) : Eigen::VectorXd::Constant(s.samples.size(), s.params.spacing);
  EXPECT_EQ(b->sampleSpacing, h);
}

TEST(BoundSnapshot, TakesTheSpacingsOverOnlyWhileTheSamplesAreTheSame) {
  app::Session s = boundStarFor(1);
  BoundSnapshot before = *makeBoundSnapshot(s);
  before.sampleSpacing.setConstant(-1.0);  // marks what is taken over
  app::reoptimize(s, Method::QEC);         // a job that keeps the samples
  const auto same = makeBoundSnapshot(s, &before);
  EXPECT_EQ(same->method, Method::QEC);
  EXPECT_EQ(same->sampleSpacing, before.sampleSpacing);
  const app::Session other = boundStarFor(2);  // other samples: computed anew
  const auto fresh = makeBoundSnapshot(other, &before);
  ASSERT_EQ(fresh->sampleSpacing.size(), other.samples.size());
  EXPECT_GT(fresh->sampleSpacing.minCoeff(), 0.0);
}

}  // namespace
}  // namespace kc::ui
