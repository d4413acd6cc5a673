#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>

#include "cli_run.h"
#include "session_load_error.h"
#include "kc/app/errors.h"
#include "kc/app/field_sampler.h"
#include "kc/app/file_io.h"
#include "kc/app/pipeline.h"
#include "kc/core/field/kernel_field.h"
#include "kc/core/field/mesh_field.h"

namespace kc::app {
namespace {

Cage squareCage() {
  Points C(4, 2);
  C << 12, 12, 52, 12, 52, 52, 12, 52;
  return Cage::polygon(C);
}

Session smallSession() {
  BindParams p;
  p.spacing = 4.0;
  return bind(squareCage(), 64, 64, p);
}

TEST(Session, SaveLoadRoundTripIsBitExact) {
  const auto dir = test::scratchDir("session_roundtrip");
  Session s = smallSession();
  s.pose = restPose(4);
  s.pose[1].translate = Vec2(3, -2);
  s.pose[2].rotate = 0.25;
  const std::string path = (dir / "s.kcw.json").string();
  saveSession(path, s);
  const Session t = loadSession(path);
  EXPECT_EQ(t.samples.X, s.samples.X);
  EXPECT_EQ(t.samples.kind, s.samples.kind);
  EXPECT_EQ(t.samples.edge, s.samples.edge);
  EXPECT_EQ(t.W0, s.W0);
  EXPECT_EQ(t.W, s.W);
  EXPECT_EQ(t.sigma, s.sigma);
  ASSERT_EQ(t.pose.size(), 4u);
  EXPECT_EQ(t.pose[1].translate, Vec2(3, -2));
  EXPECT_EQ(t.pose[2].rotate, 0.25);
  Points P(3, 2);
  P << 20, 30, 40.5, 17.25, 1, 63;
  EXPECT_EQ(t.field->weightsAt(P), s.field->weightsAt(P));
  const auto j = nlohmann::json::parse(sessionToJson(s));
  EXPECT_EQ(j["field"]["kind"], "kernel");
}

TEST(Session, CorruptFieldsAreNamed) {
  const auto dir = test::scratchDir("session_corrupt");
  const Session s = smallSession();
  const nlohmann::json good = nlohmann::json::parse(sessionToJson(s, WeightsForm::Rows));  // the compact form: session_weights_test
  auto expectError = [&](const nlohmann::json& j, const std::string& part) {
    const std::string path = (dir / "bad.kcw.json").string();
    test::writeText(path, j.dump());
    try {
      loadSession(path);
      ADD_FAILURE() << "no error for " << part;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
  };
  nlohmann::json j = good;
  j["weights"]["optimized"].erase(j["weights"]["optimized"].begin());
  expectError(j, "weights.optimized has");
  j = good;
  j["weights"]["initial"][5] = {0.5};
  expectError(j, "weights.initial[5] must have 4 weights");
  j = good;
  j["samples"]["kinds"][7] = "inside";
  expectError(j, "samples.kinds[7]");
  j = good;
  j["samples"]["points"][0] = {0, 0};
  expectError(j, "differs from cage point 0");
  j = good;
  j["params"]["method"] = "newton";
  expectError(j, "params.method");
  j = good;
  j["params"]["target_floor"] = 0.5;
  expectError(j, "params.target_floor must be in [0, 0.5)");
  j["params"]["target_floor"] = -0.01;
  expectError(j, "params.target_floor must be in [0, 0.5)");
  j = good;
  j["image_upright"] = "yes";
  expectError(j, "image_upright must be true or false");
  j = good;
  j["params"]["sigma"] = -1;
  expectError(j, "params.sigma");
  j = good;
  j["version"] = 7;
  expectError(j, "unsupported version 7");
  j = good;
  j["pose"] = {{"handles", nlohmann::json::array({nlohmann::json::object()})}};
  expectError(j, "pose.handles has 1 entries but the cage has 4");
  const std::string text = sessionToJson(s);
  test::writeText(dir / "cut.kcw.json", text.substr(0, text.size() / 2));
  EXPECT_THROW(loadSession((dir / "cut.kcw.json").string()), InputError);
}

TEST(Session, ReoptimizeSubsetTouchesOnlyThoseRows) {
  Session s = smallSession();
  const Weights before = s.W;
  // Paint: change the targets of a few interior samples, re-optimize only them.
  std::vector<Index> painted;
  for (Index i = 0; i < s.samples.size() && painted.size() < 5; ++i)
    if (s.samples.kind[static_cast<std::size_t>(i)] == SampleKind::Interior) painted.push_back(i);
  ASSERT_EQ(painted.size(), 5u);
  for (Index i : painted) s.W0(i, 0) += 0.3;
  std::vector<Index> columns;
  reoptimize(s, Method::QP, painted, &columns);
  EXPECT_FALSE(columns.empty());
  // Only the changed columns were re-solved, yet the field equals a full solve.
  const auto& field = dynamic_cast<const KernelField&>(*s.field);
  const KernelCoefficients full = field.interpolator().solve(s.W);
  EXPECT_LT((full.U - field.kernelCoefficients().U).cwiseAbs().maxCoeff(), 1e-9 * full.U.cwiseAbs().maxCoeff());
  EXPECT_LT((full.B - field.kernelCoefficients().B).cwiseAbs().maxCoeff(), 1e-9);
  for (Index c = 0; c < s.W.cols(); ++c) {
    const bool listed = std::find(columns.begin(), columns.end(), c) != columns.end();
    bool differs = false;
    for (Index i = 0; i < s.W.rows(); ++i) differs = differs || s.W(i, c) != before(i, c);
    EXPECT_EQ(listed, differs) << "column " << c;
  }
  // The painted rows change; so may the exterior rows continued from them (KcParams::guardLobes),
  // and no other.
  const std::vector<Index> rederived = rederivedRows(s, painted);
  EXPECT_GE(rederived.size(), painted.size());
  Index changed = 0;
  for (Index i = 0; i < s.samples.size(); ++i) {
    const bool isPainted = std::find(rederived.begin(), rederived.end(), i) != rederived.end();
    if (!isPainted) {
      EXPECT_EQ(s.W.row(i), before.row(i)) << "row " << i;
    } else if (s.W.row(i) != before.row(i)) {
      ++changed;
    }
  }
  EXPECT_GT(changed, 0);
}

TEST(FieldSampler, MatchesTheFieldAndUpdatesOnlyGivenColumns) {
  Session s = smallSession();
  Points P(200, 2);
  for (Index i = 0; i < P.rows(); ++i) P.row(i) << 0.3 * static_cast<double>(i % 20) * 10.0 + 1.5, 0.31 * static_cast<double>(i / 10) * 10.0;
  FieldSampler sampler(*s.field, P);
  const Weights direct = s.field->weightsAt(P);
  Weights W = sampler.evaluate(*s.field);
  EXPECT_LT((W - direct).cwiseAbs().maxCoeff(), 1e-12);
  // Change the sample weights of column 2 only and update that column of the field: updating
  // column 2 alone at the cached points gives the full result.
  Weights Ws = s.W;
  Ws.col(2) *= 0.5;
  const Index cols[] = {2};
  s.field->update(Ws, cols);
  const Weights expected = s.field->weightsAt(P);
  const Weights old = W;
  sampler.updateColumns(*s.field, cols, W);
  EXPECT_LT((W - expected).cwiseAbs().maxCoeff(), 1e-14);
  for (Index c : {0, 1, 3}) EXPECT_EQ(W.col(c), old.col(c));
  EXPECT_NE(W.col(2), old.col(2));
}


/// A session whose field is a hand-built mesh (what a mesh backend such as LBC stores): the square
/// cage's corners plus its centre, four triangles, per-vertex weights, no targets.
Session meshSession() {
  Session s;
  s.cage = squareCage();
  s.imageWidth = s.imageHeight = 64;
  s.params.backend = "lbc";  // a mesh field belongs to a mesh backend
  s.sigma = 1.0;  // unused by a mesh field
  Points V(5, 2);
  V << s.cage.C, 32, 32;
  Weights W = Weights::Zero(5, 4);
  for (Index i = 0; i < 4; ++i) W(i, i) = 1.0;
  W.row(4).setConstant(0.25);
  s.samples.X = V;
  s.samples.kind = {SampleKind::Control, SampleKind::Control, SampleKind::Control, SampleKind::Control, SampleKind::Interior};
  s.samples.edge.setConstant(5, 2, -1);
  s.W = W;
  s.field = std::make_unique<MeshField>(V, Triangles{{0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}}, W);
  return s;
}

TEST(Session, MeshFieldRoundTrip) {
  const auto dir = test::scratchDir("session_mesh");
  const Session s = meshSession();
  const std::string path = (dir / "mesh.kcw.json").string();
  saveSession(path, s);
  const auto j = nlohmann::json::parse(readTextFile(path));
  EXPECT_EQ(j["field"]["kind"], "mesh");
  EXPECT_EQ(j["field"]["triangles"].size(), 4u);
  EXPECT_FALSE(j["weights"].contains("initial") || j["weights"].contains("initial_b64"));  // no targets
  const Session t = loadSession(path);
  const auto* mesh = dynamic_cast<const MeshField*>(t.field.get());
  ASSERT_NE(mesh, nullptr);
  EXPECT_EQ(mesh->vertices(), dynamic_cast<const MeshField&>(*s.field).vertices());
  EXPECT_EQ(mesh->triangles(), dynamic_cast<const MeshField&>(*s.field).triangles());
  Points P(3, 2);
  P << 20, 30, 40.5, 17.25, 1, 1;  // the last point is outside the mesh
  EXPECT_EQ(t.field->weightsAt(P), s.field->weightsAt(P));
  EXPECT_NEAR(t.field->weightsAt(P).row(0).sum(), 1.0, 1e-12);
  EXPECT_FALSE(t.field->contains(Vec2(1, 1)));
  // What the GUI greys out: no targets to paint or re-optimize, no weights outside the mesh.
  const BackendCapabilities caps = sessionCapabilities(t);
  EXPECT_FALSE(caps.painting);
  EXPECT_FALSE(caps.methods);
  EXPECT_FALSE(caps.outsideCage);
  EXPECT_FALSE(caps.why.empty());
  Session u = loadSession(path);
  EXPECT_THROW(reoptimize(u, Method::QP), std::invalid_argument);
}

TEST(Session, MalformedMeshFieldIsNamed) {
  const auto dir = test::scratchDir("session_mesh_bad");
  nlohmann::json j = nlohmann::json::parse(sessionToJson(meshSession()));
  j["field"]["triangles"][2] = {2, 3, 9};
  const std::string path = (dir / "bad.kcw.json").string();
  test::writeText(path, j.dump());
  try {
    loadSession(path);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("field.triangles[2][2] = 9 is out of range"), std::string::npos) << e.what();
  }
  j["field"]["kind"] = "voxels";
  test::writeText(path, j.dump());
  EXPECT_THROW(loadSession(path), InputError);
}

// Well-formed but wrong: weights that are not a partition of unity or do not reproduce the
// samples, a field of the other backend's kind, a mesh that does not cover the cage.
TEST(Session, SemanticallyWrongSessionsAreRefusedNamingTheCheck) {
  const auto dir = test::scratchDir("session_semantic");
  const nlohmann::json kernel = nlohmann::json::parse(sessionToJson(smallSession(), WeightsForm::Rows));
  auto expectError = [&](const nlohmann::json& j, const std::string& part) {
    const std::string e = test::loadError(j, (dir / "bad.kcw.json").string());
    EXPECT_NE(e.find(part), std::string::npos) << "expected '" << part << "' in: " << e;
    EXPECT_NE(e.find("bad.kcw.json: "), std::string::npos) << e;
  };
  nlohmann::json j = kernel;
  for (auto& row : j["weights"]["optimized"])
    for (auto& w : row) w = 0.0;
  expectError(j, "weights.optimized row 0 sums to 0 (partition of unity");
  j = kernel;
  std::swap(j["weights"]["optimized"][10][0], j["weights"]["optimized"][10][2]);  // still sums to 1
  expectError(j, "weights.optimized row 10 reproduces its sample");
  j = kernel;
  j["field"] = nlohmann::json::parse(sessionToJson(meshSession()))["field"];
  expectError(j, "field.kind \"mesh\" does not match params.backend \"kc\"");

  const nlohmann::json mesh = nlohmann::json::parse(sessionToJson(meshSession(), WeightsForm::Rows));
  EXPECT_EQ(test::loadError(mesh, (dir / "bad.kcw.json").string()), "(loaded without error)");
  j = mesh;
  j["field"]["kind"] = "kernel";
  expectError(j, "field.kind \"kernel\" does not match params.backend \"lbc\"");
  j = mesh;
  for (auto& t : j["field"]["triangles"]) t = {0, 1, 4};  // every triangle the same
  expectError(j, "field.triangles[1] repeats field.triangles[0]");
  j = mesh;
  j["field"]["triangles"][2] = {3, 2, 4};
  expectError(j, "field.triangles[2] is inverted");
  j = mesh;
  j["field"]["vertices"][4] = {1e6, 1e6};
  expectError(j, "field.vertices[4] = (1e+06, 1e+06) lies outside the cage's bounds");
  j = mesh;
  j["field"]["triangles"].erase(3);
  expectError(j, "field.triangles cover 1200 px² but the cage encloses 1600 px²");
  j = mesh;
  j["field"]["weights"][4] = {0.5, 0.0, 0.5, 0.0};  // sums to 1 and reproduces (32, 32): accepted
  EXPECT_EQ(test::loadError(j, (dir / "bad.kcw.json").string()), "(loaded without error)");
  j["field"]["weights"][4] = {0.5, 0.5, 0.0, 0.0};
  expectError(j, "field.weights row 4 reproduces its sample");
}

TEST(Session, SolverReportsAreSavedAndRead) {
  const auto dir = test::scratchDir("session_reports");
  Session s = smallSession();
  EXPECT_GT(s.report.optimize.solved, 0);
  s.report.optimize.failed = 3;
  s.report.init.fallbackSamples = 2;
  const std::string path = (dir / "r.kcw.json").string();
  saveSession(path, s);
  const auto j = nlohmann::json::parse(readTextFile(path));
  EXPECT_EQ(j["reports"]["optimize"]["failed"], 3);
  EXPECT_EQ(j["reports"]["problems"].size(), 2u);
  const Session t = loadSession(path);
  EXPECT_EQ(t.report.optimize.failed, 3);
  EXPECT_EQ(t.report.optimize.solved, s.report.optimize.solved);
  EXPECT_EQ(t.report.init.fallbackSamples, 2);
  EXPECT_TRUE(t.report.anyProblem());
  EXPECT_NE(t.report.summary().find("WARNING"), std::string::npos);
}

/// Every backend's parameters go through their description (BackendParameter): set away from
/// their defaults they come back from the file, the kc backend's at the top of params (σ and the
/// locality rule through its own keys), the LBC solver's in params.lbc also in a kc session.
TEST(Session, EveryBackendsParametersComeBackFromTheFile) {
  Session s = smallSession();
  KcParams& kc = s.params.kc;
  kc.sigma = s.sigma;  // a σ set by hand
  kc.init.method = InitMethod::InverseDistance;
  kc.init.iterations = 7;
  kc.targetFloor = 0.125;
  kc.guardLobes = false;
  kc.method = Method::QEC;
  kc.qpAllowance = 0.25;
  kc.linearEdges = true;
  kc.exactLines = false;
  s.params.lbc = {LbcTau::Linear, 1e-4, 123};
  for (const Locality locality : {Locality{Locality::Rule::Pixels, 17.0}, Locality{Locality::Rule::Spacings, 2.5},
                                  Locality{Locality::Rule::Automatic, 0.0}, Locality{Locality::Rule::Off, 0.0}}) {
    kc.locality = locality;
    const Session t = sessionFromJson(sessionToJson(s), "mem.kcw.json");
    const KcParams& k = t.params.kc;
    EXPECT_EQ(k.locality, locality);
    EXPECT_EQ(k.sigma, s.sigma);
    EXPECT_EQ(k.init.method, InitMethod::InverseDistance);
    EXPECT_EQ(k.init.iterations, 7);
    EXPECT_EQ(k.targetFloor, 0.125);
    EXPECT_FALSE(k.guardLobes);
    EXPECT_EQ(k.method, Method::QEC);
    EXPECT_EQ(k.qpAllowance, 0.25);
    EXPECT_EQ(k.interp, InterpMode::Exact);
    EXPECT_TRUE(k.linearEdges);
    EXPECT_FALSE(k.exactLines);
    EXPECT_EQ(t.params.lbc.tau, LbcTau::Linear);
    EXPECT_EQ(t.params.lbc.tolerance, 1e-4);
    EXPECT_EQ(t.params.lbc.maxIterations, 123);
  }
  kc.sigma = 0.0;  // automatic: the file keeps the σ used and says it was chosen
  const auto j = nlohmann::json::parse(sessionToJson(s));
  EXPECT_EQ(j["params"]["sigma"].get<double>(), s.sigma);
  EXPECT_TRUE(j["params"]["sigma_auto"].get<bool>());
  EXPECT_EQ(sessionFromJson(j.dump(), "mem.kcw.json").params.kc.sigma, 0.0);
}

/// A file written before an option existed reads the behaviour it was bound with: each key's
/// absent value (BackendParameter::absentValue), not today's default.
TEST(Session, KeysAnOlderFileLacksReadTheirAbsentValues) {
  auto j = nlohmann::json::parse(sessionToJson(smallSession()));
  for (const char* key : {"target_floor", "guard_lobes", "exact_lines", "linear_edges", "locality", "locality_spacings",
                          "sigma_auto", "heat_iterations", "init", "lbc", "qp_allowance"})
    j["params"].erase(key);
  const Session t = sessionFromJson(j.dump(), "old.kcw.json");
  const KcParams& k = t.params.kc;
  EXPECT_EQ(k.targetFloor, 0.0);
  EXPECT_FALSE(k.guardLobes);
  EXPECT_FALSE(k.exactLines);
  EXPECT_FALSE(k.linearEdges);
  EXPECT_EQ(k.qpAllowance, 0.0);  // the thesis's Euclidean QP
  EXPECT_EQ(k.locality.rule, Locality::Rule::Off);
  EXPECT_EQ(k.sigma, t.sigma);  // no sigma_auto: the σ written was set by hand
  EXPECT_EQ(k.init.iterations, InitOptions{}.iterations);
  EXPECT_EQ(k.init.method, InitMethod::HeatLinear);
  EXPECT_EQ(t.params.lbc.tau, LbcParams{}.tau);
  j["params"]["guard_lobes"] = 1;
  try {
    sessionFromJson(j.dump(), "old.kcw.json");
    ADD_FAILURE() << "a number for a Boolean key was read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("params.guard_lobes must be true or false"), std::string::npos) << e.what();
  }
}

TEST(Session, OldFormatSessionStillLoads) {
  // Written by kcwarp-cli bind before the field and reports blocks existed (checked in).
  const std::string path = std::string(KC_SOURCE_DIR) + "/tests/data/old_format.kcw.json";
  const auto j = nlohmann::json::parse(readTextFile(path));
  ASSERT_FALSE(j.contains("field"));
  ASSERT_FALSE(j.contains("reports"));
  const Session s = loadSession(path);
  ASSERT_TRUE(s.hasField());
  EXPECT_NE(dynamic_cast<const KernelField*>(s.field.get()), nullptr);
  EXPECT_EQ(s.W0.rows(), s.samples.size());
  EXPECT_FALSE(s.report.anyProblem());
  // The rebuilt field interpolates the stored weights (Lagrange at the samples) and is a partition of unity.
  const Weights W = s.field->weightsAt(s.samples.X);
  EXPECT_LT((W - s.W).cwiseAbs().maxCoeff(), 1e-9);
  Points P(1, 2);
  P << 30.5, 29.25;
  EXPECT_NEAR(s.field->weightsAt(P).row(0).sum(), 1.0, 1e-9);
  EXPECT_TRUE(sessionCapabilities(s).painting);
}

}  // namespace
}  // namespace kc::app
