#include "kc/app/file_io.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "cli_run.h"
#include "kc/app/errors.h"

namespace kc::app {
namespace {

using test::scratchDir;
using test::writeText;

/// The message of the InputError that f throws, or "" when it throws none.
template <class F>
std::string inputError(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

TEST(CageFile, LoadsPolygonAndRoundTrips) {
  const auto dir = scratchDir("cage_roundtrip");
  writeText(dir / "c.json", R"({"version": 1, "points": [[10,10],[90,10],[90,90],[10,90]], "closed": true, "image_size": [100,100]})");
  const Cage c = loadCage((dir / "c.json").string());
  ASSERT_EQ(c.size(), 4);
  EXPECT_EQ(c.edges.size(), 4u);
  EXPECT_DOUBLE_EQ(c.C(2, 0), 90.0);
  saveCage((dir / "d.json").string(), c);
  const Cage d = loadCage((dir / "d.json").string());
  EXPECT_EQ(d.C, c.C);
  EXPECT_EQ(d.edges, c.edges);
}

TEST(CageFile, BadInputNamesFileAndProblem) {
  const auto dir = scratchDir("cage_bad");
  const std::string path = (dir / "c.json").string();
  EXPECT_TRUE(contains(inputError([&] { loadCage((dir / "missing.json").string()); }), "missing.json: no such file"));
  writeText(path, R"({"version": 1, "points": [[0,0],[10,0],)");
  const std::string truncated = inputError([&] { loadCage(path); });
  EXPECT_TRUE(contains(truncated, path)) << truncated;
  EXPECT_TRUE(contains(truncated, "truncated")) << truncated;
  writeText(path, R"({"version": 1, "points": [[0,0],[10,0],[10,NaN]]})");
  EXPECT_TRUE(contains(inputError([&] { loadCage(path); }), "malformed JSON"));
  writeText(path, R"({"version": 2, "points": [[0,0],[10,0],[10,10]]})");
  EXPECT_TRUE(contains(inputError([&] { loadCage(path); }), "unsupported version 2"));
  writeText(path, R"({"points": [[0,0],[10,0],[10,10]]})");
  EXPECT_TRUE(contains(inputError([&] { loadCage(path); }), "missing key 'version'"));
  writeText(path, R"({"version": 1, "pts": []})");
  EXPECT_TRUE(contains(inputError([&] { loadCage(path); }), "missing key 'points'"));
  writeText(path, R"({"version": 1, "points": [[0,0],[10,0],[10]]})");
  EXPECT_TRUE(contains(inputError([&] { loadCage(path); }), "points[2] must be a pair"));
  writeText(path, R"({"version": 1, "points": [[0,0],[10,10],[10,0],[0,10]]})");
  EXPECT_TRUE(contains(inputError([&] { loadCage(path); }), "self-intersecting"));
  writeText(path, R"({"version": 1, "points": [[0,0],[1,1],[2,2]]})");
  EXPECT_TRUE(contains(inputError([&] { loadCage(path); }), "collinear"));
  writeText(path, R"({"version": 1, "points": [[0,0],[10,0],[1e999,5]]})");
  EXPECT_NE(inputError([&] { loadCage(path); }), "");
}

TEST(PoseFile, BothFormsAndWrongCounts) {
  const auto dir = scratchDir("pose");
  Points C(3, 2);
  C << 0, 0, 10, 0, 0, 10;
  writeText(dir / "p.json", R"({"version": 1, "positions": [[1,0],[10,2],[0,10]]})");
  Pose p = loadPose((dir / "p.json").string(), C);
  ASSERT_EQ(p.size(), 3u);
  EXPECT_EQ(p[0].translate, Vec2(1, 0));
  EXPECT_EQ(p[1].translate, Vec2(0, 2));
  writeText(dir / "h.json", R"({"version": 1, "handles": [{"translate": [1,2], "rotate": 0.5}, {}, {"rotate": -1}]})");
  p = loadPose((dir / "h.json").string(), C);
  EXPECT_EQ(p[0].translate, Vec2(1, 2));
  EXPECT_DOUBLE_EQ(p[0].rotate, 0.5);
  EXPECT_DOUBLE_EQ(p[2].rotate, -1.0);
  savePose((dir / "s.json").string(), p);
  const Pose q = loadPose((dir / "s.json").string(), C);
  EXPECT_EQ(q[0].translate, p[0].translate);
  EXPECT_EQ(q[2].rotate, p[2].rotate);

  writeText(dir / "w.json", R"({"version": 1, "positions": [[1,0],[10,2]]})");
  EXPECT_TRUE(contains(inputError([&] { loadPose((dir / "w.json").string(), C); }),
                       "positions has 2 entries but the cage has 3 control points"));
  writeText(dir / "w.json", R"({"version": 1, "handles": [{"rotate": "a lot"}, {}, {}]})");
  EXPECT_TRUE(contains(inputError([&] { loadPose((dir / "w.json").string(), C); }), "handles[0].rotate must be a number"));
  writeText(dir / "w.json", R"({"version": 1})");
  EXPECT_TRUE(contains(inputError([&] { loadPose((dir / "w.json").string(), C); }), "missing key"));
}

TEST(AtomicSave, ReplacesWholeFileAndLeavesNoTemporaries) {
  const auto dir = scratchDir("atomic");
  const std::string path = (dir / "f.txt").string();
  writeFileAtomic(path, "first");
  writeFileAtomic(path, "second version");
  EXPECT_EQ(test::slurp(path), "second version");
  int files = 0;
  for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir)) ++files;
  EXPECT_EQ(files, 1);
  // A save into a folder that does not exist fails with the path and keeps nothing.
  const std::string bad = (dir / "no" / "such" / "f.txt").string();
  EXPECT_TRUE(contains(inputError([&] { writeFileAtomic(bad, "x"); }), "does not exist"));
  EXPECT_FALSE(std::filesystem::exists(bad));
}

}  // namespace
}  // namespace kc::app
