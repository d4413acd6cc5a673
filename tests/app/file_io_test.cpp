#include "kc/app/file_io.h"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>
#include <string>

#include "cli_run.h"
#include "kc/app/errors.h"
#include "kc/app/points_csv.h"

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

TEST(AtomicSave, NamesUpToNameMaxWork) {
  const auto dir = scratchDir("atomic_long_name");
  for (const std::size_t length : {237u, 238u, 250u, 255u}) {
    const std::string path = (dir / (std::string(length - 4, 'n') + ".png")).string();
    writeFileAtomic(path, "first");
    writeFileAtomic(path, "second");  // replaces: through a temporary name, which must fit NAME_MAX too
    EXPECT_EQ(test::slurp(path), "second") << length;
  }
  int files = 0;
  for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir)) ++files;
  EXPECT_EQ(files, 4);
}

// A command's outputs go in place together: when one cannot be written, none is replaced and no
// temporary file is left.
TEST(OutputBatch, AFailedOutputLeavesEveryOutputAsItWas) {
  namespace fs = std::filesystem;
  const auto dir = scratchDir("output_batch");
  fs::create_directories(dir / "ok");
  fs::create_directories(dir / "gone");
  writeText(dir / "ok" / "a.json", "old a");
  OutputBatch batch;
  batch.reserve((dir / "ok" / "a.json").string());
  batch.reserve((dir / "ok" / "new.json").string());
  batch.reserve((dir / "gone" / "b.png").string());
  batch.set((dir / "ok" / "a.json").string(), "new a");
  batch.set((dir / "ok" / "new.json").string(), "new");
  batch.set((dir / "gone" / "b.png").string(), "b");
  fs::remove_all(dir / "gone");  // the last output's folder disappears after the checks
  EXPECT_TRUE(contains(inputError([&] { batch.commit(); }), "b.png")) << "no InputError naming the failed output";
  EXPECT_EQ(test::slurp(dir / "ok" / "a.json"), "old a");
  int files = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir / "ok")) ++files;
  EXPECT_EQ(files, 1) << "an output or a temporary was left";

  OutputBatch good;
  good.set((dir / "ok" / "a.json").string(), "new a");
  good.set((dir / "ok" / "new.json").string(), "new");
  good.commit();
  EXPECT_EQ(test::slurp(dir / "ok" / "a.json"), "new a");
  EXPECT_EQ(test::slurp(dir / "ok" / "new.json"), "new");
}

TEST(AtomicSave, KeepsModeRefusesSpecialFilesAndWritesThroughSymlinks) {
  namespace fs = std::filesystem;
  const auto dir = scratchDir("atomic_special");
  const fs::path ro = dir / "ro.txt";
  writeText(ro, "old");
  fs::permissions(ro, fs::perms::owner_read | fs::perms::group_read);
  writeFileAtomic(ro.string(), "new");
  EXPECT_EQ(test::slurp(ro), "new");
  EXPECT_EQ(fs::status(ro).permissions() & fs::perms::all, fs::perms::owner_read | fs::perms::group_read);

  ASSERT_EQ(::mkfifo((dir / "fifo").c_str(), 0600), 0);
  EXPECT_TRUE(contains(inputError([&] { writeFileAtomic((dir / "fifo").string(), "x"); }), "not a regular file"));
  EXPECT_TRUE(fs::is_fifo(dir / "fifo"));
  EXPECT_TRUE(contains(inputError([&] { writeFileAtomic(dir.string(), "x"); }), "is a folder"));

  fs::create_directory(dir / "sub");
  writeText(dir / "sub" / "target.txt", "old");
  fs::create_symlink("sub/target.txt", dir / "link.txt");
  writeFileAtomic((dir / "link.txt").string(), "through");
  EXPECT_TRUE(fs::is_symlink(dir / "link.txt"));
  EXPECT_EQ(test::slurp(dir / "sub" / "target.txt"), "through");
  // A dangling link creates the file it names.
  fs::create_symlink("sub/new.txt", dir / "dangling.txt");
  writeFileAtomic((dir / "dangling.txt").string(), "created");
  EXPECT_EQ(test::slurp(dir / "sub" / "new.txt"), "created");
  for (const auto& d : {dir, dir / "sub"})
    for (const auto& e : fs::directory_iterator(d)) EXPECT_FALSE(contains(e.path().string(), ".tmp")) << e.path();
}

TEST(BoundedRead, RefusesSpecialAndOversizedFilesWithoutBlocking) {
  const auto dir = scratchDir("bounded_read");
  EXPECT_TRUE(contains(inputError([&] { readTextFile("/dev/zero"); }), "not a regular file"));
  ASSERT_EQ(::mkfifo((dir / "fifo").c_str(), 0600), 0);
  EXPECT_TRUE(contains(inputError([&] { readTextFile((dir / "fifo").string()); }), "not a regular file"));
  EXPECT_TRUE(contains(inputError([&] { readTextFile(dir.string()); }), "is a folder"));
  EXPECT_TRUE(contains(inputError([&] { readTextFile((dir / "none").string()); }), "no such file"));
  writeText(dir / "ten.txt", "0123456789");
  EXPECT_EQ(readTextFile((dir / "ten.txt").string(), 10), "0123456789");
  EXPECT_TRUE(contains(inputError([&] { readTextFile((dir / "ten.txt").string(), 9); }), "more than the 9 bytes"));
}

TEST(PointsCsv, HeaderOnlyWhenNoFieldLooksLikeANumber) {
  EXPECT_EQ(parsePointsCsv("x,y\n1,2\n", "p").rows(), 1);
  EXPECT_EQ(parsePointsCsv(" 1 , 2 \r\n\n3,4", "p").rows(), 2);
  EXPECT_TRUE(contains(inputError([] { parsePointsCsv("10,nan\n1,2\n3,4\n", "p.csv"); }), "p.csv: line 1"));
  EXPECT_TRUE(contains(inputError([] { parsePointsCsv("x,y\n1,2\nx,y\n", "p.csv"); }), "line 3"));
  EXPECT_TRUE(contains(inputError([] { parsePointsCsv("1,1e300\n", "p.csv"); }), "line 1"));
  EXPECT_TRUE(contains(inputError([] { parsePointsCsv("x,y\n", "p.csv"); }), "no points"));
}

// Messages stay one short line whatever the input held: a parse error quotes an excerpt with its
// byte offset (nlohmann's "last read" token can be the rest of the file), control characters in
// a path are escaped, and any part beyond the limits keeps its head and tail.
TEST(Errors, MessagesAreOneShortLineWhateverTheInputHolds) {
  const auto dir = scratchDir("errors_bounded");
  const std::string path = (dir / "c.json").string();
  writeText(path, "{\"version\": 1, \"points\": [[0,0],[10,0],[0,10]], \"name\": \"" + std::string(100000, 'A'));
  const std::string unterminated = inputError([&] { loadCage(path); });
  EXPECT_LT(unterminated.size(), 400u) << unterminated;  // the error is found at the end of the file (57 + 100000 bytes)
  EXPECT_TRUE(contains(unterminated, path + ": malformed JSON at byte 100057, near '...AAAAAAAAAAAAAAAAAAAAAAAA'")) << unterminated;
  EXPECT_TRUE(contains(unterminated, "missing closing quote")) << unterminated;
  EXPECT_TRUE(contains(unterminated, "(the file looks truncated)")) << unterminated;
  // A picture is named as one; other bytes that are not text are quoted as \xNN.
  writeText(path, std::string("\x89PNG\r\n\x1a\n\0\0\0\rIHDR", 16) + std::string(50000, '\x7f'));
  const std::string picture = inputError([&] { loadCage(path); });
  EXPECT_TRUE(contains(picture, path + ": this file is a PNG image, not JSON text")) << picture;
  EXPECT_EQ(picture.find('\n'), std::string::npos);
  writeText(path, std::string("\x01\x02\x7f" "junk") + std::string(50000, '\x7f'));
  const std::string binary = inputError([&] { loadCage(path); });
  EXPECT_TRUE(contains(binary, "malformed JSON at byte 0, near '\\x01\\x02\\x7fjunk")) << binary;
  EXPECT_EQ(binary.find('\n'), std::string::npos);
  // A value quoted from a file is cut.
  writeText(path, "{\"version\": 1, \"points\": [[0,0],[10,0],[0,10]], \"edges\": [[0, " + std::string(5000, '9') + "]]}");
  const std::string big = inputError([&] { loadCage(path); });
  EXPECT_LT(big.size(), 300u) << big;
  // A newline in a path, and parts beyond the limits.
  const InputError e("dir/a\nb.json", std::string(3000, 'x') + "END");
  const std::string m = e.what();
  EXPECT_EQ(m.find('\n'), std::string::npos);
  EXPECT_EQ(m.rfind("dir/a\\nb.json: xxx", 0), 0u) << m;
  EXPECT_LE(m.size(), kMaxMessageWhere + kMaxMessageWhat + 12);
  EXPECT_TRUE(contains(m, " ... ")) << m;
  EXPECT_EQ(m.substr(m.size() - 3), "END");
  EXPECT_EQ(oneLine("≤≤≤≤≤≤", 9), "≤≤ ... ≤");  // cut at character boundaries
}

}  // namespace
}  // namespace kc::app

namespace kc::app {
namespace {

// Exit codes (ARCHITECTURE.md): user data a lower layer rejects is bad input (InputError, exit 2)
// only where the app hands it over through asUserInput; any other std::invalid_argument is
// misuse of an internal API and stays one (kcwarp-cli: exit 1).
TEST(Errors, AsUserInputNamesWhereAndPassesOtherFailuresThrough) {
  try {
    asUserInput("cage.json", [] { throw std::invalid_argument("points 3 and 4 coincide"); });
    FAIL() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "cage.json: points 3 and 4 coincide");
  }
  EXPECT_THROW(asUserInput("x", [] { throw std::runtime_error("internal"); }), std::runtime_error);
  EXPECT_EQ(asUserInput("x", [] { return 7; }), 7);
}

}  // namespace
}  // namespace kc::app
