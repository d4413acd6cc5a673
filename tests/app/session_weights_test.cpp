// The weight matrices of session files: the compact form (base64 of little-endian doubles, the
// default) round-trips bit-exactly and is refused with the file and key named when corrupt;
// the rows form (older files) still loads to the same session.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>

#include "cli_run.h"
#include "session_load_error.h"
#include "kc/app/errors.h"
#include "kc/app/file_io.h"
#include "kc/app/pipeline.h"
#include "kc/core/field/kernel_field.h"

namespace kc::app {
namespace {

using nlohmann::json;

Session boundSquare() {
  Points C(4, 2);
  C << 12, 12, 52, 12, 52, 52, 12, 52;
  BindParams p;
  p.spacing = 4.0;
  return bind(Cage::polygon(C), 64, 64, p);
}

const Session& square() {
  static const Session s = boundSquare();
  return s;
}

/// A copy of square() to edit (sessions own their field and do not copy).
Session editableSquare() { return sessionFromJson(sessionToJson(square()), "square.kcw.json"); }

/// The little-endian bytes of the doubles in the compact block, decoded independently of kcwarp
/// (RFC 4648 alphabet, '=' padding).
std::vector<double> decodeIndependently(const json& block) {
  static const std::string alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  const std::string text = block["base64"];
  std::vector<unsigned char> bytes;
  for (std::size_t i = 0; i + 4 <= text.size(); i += 4) {
    unsigned v = 0, pad = 0;
    for (std::size_t k = 0; k < 4; ++k) {
      const char c = text[i + k];
      v <<= 6;
      if (c == '=') ++pad;
      else v |= unsigned(alphabet.find(c));
    }
    for (unsigned k = 0; k < 3 - pad; ++k) bytes.push_back(static_cast<unsigned char>(v >> (16 - 8 * k)));
  }
  std::vector<double> out(bytes.size() / 8);
  for (std::size_t d = 0; d < out.size(); ++d) {
    std::uint64_t u = 0;
    for (int b = 7; b >= 0; --b) u = (u << 8) | bytes[8 * d + std::size_t(b)];  // little-endian
    std::memcpy(&out[d], &u, 8);
  }
  return out;
}

using test::loadError;

TEST(SessionWeights, CompactFormIsTheDefaultAndRoundTripsBitExactly) {
  const auto dir = test::scratchDir("session_weights_roundtrip");
  Session s = editableSquare();
  // Values whose decimal text would need all 17 digits, and a negative zero. Each edit moves its
  // row along (1, -1, 1, -1), which the square's corners map to (0, 0) with sum 0: the rows stay a
  // partition of unity that reproduces their samples (loadSession checks both).
  const auto setKeepingConstraints = [&](Index i, Index k, double value) {
    const double d = (value - s.W(i, k)) * (k % 2 == 0 ? 1.0 : -1.0);
    for (Index c = 0; c < 4; ++c) s.W(i, c) += c % 2 == 0 ? d : -d;
    s.W(i, k) = value;
  };
  setKeepingConstraints(7, 1, 0.1 + 0.2);
  setKeepingConstraints(8, 2, -0.0);
  s.W0(9, 3) = std::nextafter(1.0, 2.0);
  s.field->update(s.W);  // the field follows the weights, as after any edit (its coefficients are saved too)
  const std::string path = (dir / "s.kcw.json").string();
  saveSession(path, s);
  const json j = json::parse(readTextFile(path));
  ASSERT_FALSE(j["weights"].contains("optimized"));
  const json& block = j["weights"]["optimized_b64"];
  EXPECT_EQ(block["shape"], json::array({s.samples.size(), s.cage.size()}));
  EXPECT_EQ(block["dtype"], "f64le");
  // Row by row, little-endian doubles: checked with a decoder written here.
  const std::vector<double> raw = decodeIndependently(block);
  ASSERT_EQ(raw.size(), std::size_t(s.W.size()));
  for (Index i = 0; i < s.W.rows(); ++i)
    for (Index k = 0; k < s.W.cols(); ++k) ASSERT_EQ(raw[std::size_t(i * s.W.cols() + k)], s.W(i, k)) << i << "," << k;

  const Session t = loadSession(path);
  EXPECT_EQ(t.W, s.W);
  EXPECT_EQ(t.W0, s.W0);
  EXPECT_TRUE(std::signbit(t.W(8, 2)));
  EXPECT_EQ(t.W(7, 1), 0.1 + 0.2);
  EXPECT_EQ(t.W0(9, 3), std::nextafter(1.0, 2.0));
  // Saved again, the same text.
  EXPECT_EQ(sessionToJson(t), sessionToJson(s));
}

TEST(SessionWeights, RowsFormLoadsToTheSameSession) {
  const auto dir = test::scratchDir("session_weights_rows");
  const std::string rows = sessionToJson(square(), WeightsForm::Rows);
  const json j = json::parse(rows);
  ASSERT_TRUE(j["weights"]["optimized"].is_array());
  ASSERT_FALSE(j["weights"].contains("optimized_b64"));
  const Session a = sessionFromJson(rows, "rows.kcw.json");
  const Session b = sessionFromJson(sessionToJson(square()), "compact.kcw.json");
  EXPECT_EQ(a.W, b.W);
  EXPECT_EQ(a.W0, b.W0);
  EXPECT_LT(sessionToJson(square()).size(), rows.size());
  // The checked-in file from before the compact form.
  const Session old = loadSession(std::string(KC_SOURCE_DIR) + "/tests/data/old_format.kcw.json");
  EXPECT_EQ(old.W.rows(), old.samples.size());
}

TEST(SessionWeights, CorruptCompactWeightsAreNamed) {
  const auto dir = test::scratchDir("session_weights_corrupt");
  const std::string path = (dir / "bad.kcw.json").string();
  const json good = json::parse(sessionToJson(square()));
  const std::string n = std::to_string(square().samples.size());
  auto withText = [&](const char* key, auto edit) {
    json j = good;
    edit(j["weights"][key]["base64"].get_ref<std::string&>());
    return j;
  };
  struct Case {
    const char* name;
    json file;
    std::string message;
  };
  json shape = good;
  shape["weights"]["optimized_b64"]["shape"] = {square().samples.size(), 5};
  json both = good;
  both["weights"]["optimized"] = json::array();
  json dtype = good;
  dtype["weights"]["initial_b64"]["dtype"] = "f32le";
  json missing = good;
  missing["weights"].erase("optimized_b64");
  const Case cases[] = {
      {"truncated", withText("optimized_b64", [](std::string& t) { t.resize(t.size() - 8); }),
       "weights.optimized_b64.base64 has"},
      {"truncated mid-group", withText("initial_b64", [](std::string& t) { t.resize(t.size() - 3); }),
       "(truncated)"},
      {"not base64", withText("initial_b64", [](std::string& t) { t[10] = '!'; }),
       "weights.initial_b64.base64 is not valid base64: character 10"},
      {"padding inside", withText("optimized_b64", [](std::string& t) { t[4] = '='; }), "is not valid base64"},
      {"shape", shape, "weights.optimized_b64.shape is [" + n + ", 5] but the session has " + n + " rows"},
      {"both forms", both, "weights.optimized and weights.optimized_b64 are both given"},
      {"dtype", dtype, "weights.initial_b64.dtype \"f32le\""},
      {"missing", missing, "missing key 'optimized' (or 'optimized_b64')"},
  };
  for (const Case& c : cases) {
    const std::string e = loadError(c.file, path);
    EXPECT_NE(e.find(c.message), std::string::npos) << c.name << ": " << e;
    EXPECT_NE(e.find(path), std::string::npos) << c.name << ": " << e;
  }
}

TEST(SessionWeights, CompactValuesAreRangeChecked) {
  const auto dir = test::scratchDir("session_weights_range");
  const std::string path = (dir / "bad.kcw.json").string();
  for (const double bad : {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(), 2e6}) {
    Session s = editableSquare();
    s.W(5, 1) = bad;
    const json j = json::parse(sessionToJson(s));  // the writer does not check; the reader must
    const std::string e = loadError(j, path);
    EXPECT_NE(e.find("weights.optimized_b64[5][1] is"), std::string::npos) << bad << ": " << e;
    EXPECT_NE(e.find(path), std::string::npos) << e;
  }
}

/// Points between the samples of square(): a 0.37 px offset grid over the picture.
Points probePoints() {
  Points P(21 * 21, 2);
  for (int i = 0; i < 21; ++i)
    for (int j = 0; j < 21; ++j) P.row(i * 21 + j) << 0.37 + 3.0 * i, 0.61 + 3.0 * j;
  return P;
}

const KernelField& kernelField(const Session& s) {
  const auto* field = dynamic_cast<const KernelField*>(s.field.get());
  if (!field) throw std::logic_error("not a kernel session");
  return *field;
}

TEST(SessionWeights, StoredCoefficientsLoadTheSameFieldWithoutAFactorization) {
  const json j = json::parse(sessionToJson(square()));
  ASSERT_TRUE(j["field"].contains("coefficients_b64"));
  EXPECT_EQ(j["field"]["coefficients_b64"]["shape"], json::array({square().samples.size() + 3, 4}));
  const Session loaded = sessionFromJson(j.dump(), "square.kcw.json");
  EXPECT_FALSE(kernelField(loaded).factorized());
  EXPECT_TRUE(kernelField(square()).factorized());
  const Points P = probePoints();
  EXPECT_EQ((loaded.field->weightsAt(P) - square().field->weightsAt(P)).cwiseAbs().maxCoeff(), 0.0);
  // Older files (no coefficients) and the rows form are solved on load, to the same field.
  json old = j;
  old["field"].erase("coefficients_b64");
  const Session solved = sessionFromJson(old.dump(), "square.kcw.json");
  EXPECT_TRUE(kernelField(solved).factorized());
  EXPECT_LT((solved.field->weightsAt(P) - square().field->weightsAt(P)).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_FALSE(json::parse(sessionToJson(square(), WeightsForm::Rows))["field"].contains("coefficients_b64"));
}

TEST(SessionWeights, ALoadedFieldIsFactorizedWhenEdited) {
  Session s = editableSquare();
  auto& field = const_cast<KernelField&>(kernelField(s));
  ASSERT_FALSE(field.factorized());
  Weights W = s.W;
  const Index row = s.samples.size() / 2;  // an interior or exterior sample, not a control
  W(row, 1) += 0.05;
  W(row, 2) -= 0.05;
  const std::vector<Index> columns{1, 2};
  field.update(W, columns);
  EXPECT_TRUE(field.factorized());
  KernelField fresh;
  ASSERT_EQ(fresh.compute(s.samples.X, field.interpolator().kernel(), field.interpolator().mode()).status, SolveStatus::Ok);
  fresh.update(W);
  const Points P = probePoints();
  EXPECT_LT((field.weightsAt(P) - fresh.weightsAt(P)).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LT((field.weightsAt(s.samples.X.row(row)) - W.row(row)).cwiseAbs().maxCoeff(), 1e-9);
}

TEST(SessionWeights, CoefficientsThatDoNotGiveTheWeightsBackAreSolvedAnew) {
  // Weights edited in the file after the coefficients were written: the loader solves the field
  // from the weights (the coefficients are only a stored solve).
  Session s = editableSquare();
  const Index row = s.samples.size() / 2;
  for (Index c = 0; c < 4; ++c) s.W(row, c) += c % 2 == 0 ? 0.05 : -0.05;  // still a partition of unity that reproduces
  const Session loaded = sessionFromJson(sessionToJson(s), "square.kcw.json");
  EXPECT_TRUE(kernelField(loaded).factorized());
  EXPECT_LT((loaded.field->weightsAt(s.samples.X.row(row)) - s.W.row(row)).cwiseAbs().maxCoeff(), 1e-9);
  // Corrupt coefficients are named like corrupt weights.
  const auto dir = test::scratchDir("session_weights_coefficients");
  json j = json::parse(sessionToJson(square()));
  std::string& text = j["field"]["coefficients_b64"]["base64"].get_ref<std::string&>();
  text.resize(text.size() - 8);
  const std::string e = loadError(j, (dir / "bad.kcw.json").string());
  EXPECT_NE(e.find("field.coefficients_b64.base64 has"), std::string::npos) << e;
}

}  // namespace
}  // namespace kc::app
