// The lobe bound of the default bind (KcParams::lobeBound, kc::LobeBound): the field's weights inside
// the cage stay ≥ −kLobeDepth on a fine grid, with partition of unity and reproduction exact, and
// every way a person reaches the weights sees the same bounded field: the warp mesh's sampler after a
// brush stroke, a method switch (QEC and L1 are unbounded), a saved and reopened session.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>

#include "kc/app/diagnostics.h"
#include "kc/app/field_sampler.h"
#include "kc/app/file_io.h"
#include "kc/app/pipeline.h"
#include "kc/core/field/kernel_field.h"

namespace kc::app {
namespace {

Cage boundCage(const std::string& path) { return loadCage(std::string(KC_SOURCE_DIR) + "/" + path); }

/// The bind `kcwarp-cli bind` and the GUI make: band exterior, automatic spacing.
Session bindAsAPersonDoes(const Cage& cage, int w, int h, double lobeBound = BindParams{}.kc.lobeBound) {
  BindParams p;
  p.exterior = sampling::ExteriorExtent::Band;
  p.spacing = automaticSpacing(cage, w, h, p);
  p.kc.lobeBound = lobeBound;
  return app::bind(cage, w, h, p);
}

/// A grid of `step` px over the cage's bounding box, the points inside the cage.
Points insideGrid(const Cage& cage, double step) {
  const CageQueries q(cage);
  const Vec2 lo = cage.C.colwise().minCoeff(), hi = cage.C.colwise().maxCoeff();
  std::vector<Vec2> in;
  for (double y = lo.y() + 0.25; y < hi.y(); y += step)
    for (double x = lo.x() + 0.25; x < hi.x(); x += step)
      if (q.inside(Vec2(x, y))) in.emplace_back(x, y);
  Points P(static_cast<Index>(in.size()), 2);
  for (std::size_t k = 0; k < in.size(); ++k) P.row(static_cast<Index>(k)) = in[k];
  return P;
}

/// Rows of W that the bound holds (a weight at −kLobeDepth).
Index rowsAtTheBound(const Weights& W) {
  Index n = 0;
  for (Index i = 0; i < W.rows(); ++i) n += std::abs(W.row(i).minCoeff() + kLobeDepth) < 1e-12 ? 1 : 0;
  return n;
}

TEST(LobeBoundApp, TheDefaultBindStaysAboveTheBoundOnAOnePixelGrid) {
  EXPECT_EQ(BindParams{}.kc.lobeBound, kLobeDepth);
  for (const auto& [path, w, h] : {std::tuple{std::string("images/figure.cage.json"), 320, 400},
                                   std::tuple{std::string("tests/data/locality/person.cage.json"), 360, 500},
                                   std::tuple{std::string("tests/data/locality/hand.cage.json"), 400, 440}}) {
    SCOPED_TRACE(path);
    const Cage cage = boundCage(path);
    const Session s = bindAsAPersonDoes(cage, w, h), plain = bindAsAPersonDoes(cage, w, h, 0.0);
    ASSERT_NE(s.field->lobeBound(), nullptr);
    ASSERT_EQ(plain.field->lobeBound(), nullptr);
    const Points P = insideGrid(cage, 1.0);
    const Weights W = s.field->weightsAt(P), W0 = plain.field->weightsAt(P);
    std::printf("[measured] %s: deepest weight inside on a 1-px grid %.4f (unbounded %.4f), %ld of %ld points bounded\n",
                path.c_str(), W.minCoeff(), W0.minCoeff(), static_cast<long>(rowsAtTheBound(W)), static_cast<long>(P.rows()));
    EXPECT_LT(W0.minCoeff(), -0.03) << "the unbounded field has lobes for the bound to hold";
    EXPECT_GE(W.minCoeff(), -kLobeDepth - 1e-12);
    EXPECT_LE((W.rowwise().sum().array() - 1.0).abs().maxCoeff(), 1e-9);
    EXPECT_LE(((W * cage.C) - P).cwiseAbs().maxCoeff(), 1e-7);
    // Where the unbounded field is above the bound, the weights are its own, bit for bit.
    for (Index i = 0; i < P.rows(); ++i) {
      if (W0.row(i).minCoeff() >= -kLobeDepth) {
        ASSERT_EQ(W.row(i), W0.row(i)) << "point " << i;
      }
    }
    // The drag figures of `stats` see the bounded field.
    const Diagnostics d = diagnose(s, 40000);
    EXPECT_GE(d.drag.minWeight, -kLobeDepth - 1e-12);
    EXPECT_LE(d.image.partitionOfUnity, 1e-9);
    EXPECT_LE(d.image.reproduction, 1e-7);
  }
}

TEST(LobeBoundApp, TheWarpMeshSamplerFollowsStrokesAndMethodSwitches) {
  Session s = bindAsAPersonDoes(boundCage("images/figure.cage.json"), 320, 400);
  const Points P = insideGrid(s.cage, 2.0);
  FieldSampler sampler(*s.field, P);
  Weights W = sampler.evaluate(*s.field);
  EXPECT_LE((W - s.field->weightsAt(P)).cwiseAbs().maxCoeff(), 1e-12);
  ASSERT_GT(rowsAtTheBound(W), 20);
  // One control's data changed near the right hand and only its column re-solved: the sampler
  // re-evaluates that column and projects the bounded rows again from their unbounded weights.
  std::vector<Index> near;
  for (Index i = 0; i < s.samples.size(); ++i)
    if (s.samples.kind[std::size_t(i)] == SampleKind::Interior && (s.samples.X.row(i) - Vec2(230, 150).transpose()).norm() < 30)
      near.push_back(i);
  ASSERT_GT(near.size(), 5u);
  for (Index i : near) s.W(i, 6) += 0.05;
  const Index six[] = {6};
  s.field->update(s.W, six);
  const Weights before = W;
  sampler.updateColumns(*s.field, six, W);
  EXPECT_LE((W - s.field->weightsAt(P)).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_GT((W - before).cwiseAbs().maxCoeff(), 1e-3);
  EXPECT_GE(W.minCoeff(), -kLobeDepth - 1e-12);
  // A brush stroke (the rows re-optimized from new targets): the columns it changed.
  for (Index i : near) {
    s.W0(i, 6) += 0.3;
    s.W0.row(i) /= s.W0.row(i).sum();
  }
  std::vector<Index> columns;
  reoptimize(s, Method::QP, near, &columns);
  ASSERT_FALSE(columns.empty());
  sampler.updateColumns(*s.field, columns, W);
  EXPECT_LE((W - s.field->weightsAt(P)).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_GE(W.minCoeff(), -kLobeDepth - 1e-12);
  // QEC's weights may be negative by design: no bound; back to QP, the bound again.
  reoptimize(s, Method::QEC, {}, &columns);
  EXPECT_EQ(s.field->lobeBound(), nullptr);
  sampler.updateColumns(*s.field, columns, W);
  EXPECT_LE((W - s.field->weightsAt(P)).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT(W.minCoeff(), -kLobeDepth);
  reoptimize(s, Method::QP, {}, &columns);
  ASSERT_NE(s.field->lobeBound(), nullptr);
  sampler.updateColumns(*s.field, columns, W);
  EXPECT_LE((W - s.field->weightsAt(P)).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_GE(W.minCoeff(), -kLobeDepth - 1e-12);
}

TEST(LobeBoundApp, ASessionKeepsItsBoundAndOlderFilesHaveNone) {
  const Session s = bindAsAPersonDoes(boundCage("images/figure.cage.json"), 320, 400);
  const Points P = insideGrid(s.cage, 2.0);
  const Session back = sessionFromJson(sessionToJson(s), "mem.kcw.json");
  EXPECT_EQ(back.params.kc.lobeBound, kLobeDepth);
  ASSERT_NE(back.field->lobeBound(), nullptr);
  EXPECT_FALSE(dynamic_cast<const KernelField&>(*back.field).factorized()) << "the stored coefficients were not taken";
  EXPECT_LE((back.field->weightsAt(P) - s.field->weightsAt(P)).cwiseAbs().maxCoeff(), 1e-12);
  // A file written before the option reads 0: the field it was written with, unbounded.
  nlohmann::json j = nlohmann::json::parse(sessionToJson(s));
  j["params"].erase("lobe_bound");
  const Session old = sessionFromJson(j.dump(), "mem.kcw.json");
  EXPECT_EQ(old.params.kc.lobeBound, 0.0);
  EXPECT_EQ(old.field->lobeBound(), nullptr);
  EXPECT_LT(old.field->weightsAt(P).minCoeff(), -kLobeDepth);
  // A bound out of range is refused, naming the key.
  j = nlohmann::json::parse(sessionToJson(s));
  j["params"]["lobe_bound"] = -0.1;
  try {
    (void)sessionFromJson(j.dump(), "bad.kcw.json");
    ADD_FAILURE() << "a negative lobe bound was taken";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("lobe_bound"), std::string::npos) << e.what();
  }
}

TEST(LobeBoundApp, NoBoundWithStructureLines) {
  // Lines are kept straight by weights linear along them; a projection would bend them.
  const Cage cage = boundCage("images/figure.cage.json");
  Structure st;
  st.lines.push_back(StructureLine{Vec2(150, 120), Vec2(170, 200)});
  BindParams p;
  p.spacing = 9.0;
  p.exterior = sampling::ExteriorExtent::Band;
  const Session s = app::bind(cage, st, 320, 400, p);
  EXPECT_EQ(s.field->lobeBound(), nullptr);
}

}  // namespace
}  // namespace kc::app
