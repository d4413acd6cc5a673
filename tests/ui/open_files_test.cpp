// Opening files in the GUI (document.h): a *.json file is a cage when it is meant as one — its
// problem is then a cage's — and a session otherwise; a load that fails, for bad content or for
// want of memory, names the file and leaves the document as it was.
#include <gtest/gtest.h>

#include <filesystem>
#include <new>

#include "cli_run.h"
#include "kc/app/errors.h"
#include "kc/app/file_io.h"
#include "kc/app/image_io.h"
#include "kc/ui/document.h"
#include "kc/ui/jobs.h"
#include "scene_image.h"

namespace kc::test {
namespace {

namespace fs = std::filesystem;

/// A document on a 200×150 picture at `dir`/scene.png (jobs run inline), nothing bound.
std::unique_ptr<ui::AppState> pictureDocument(const fs::path& dir) {
  app::saveImage((dir / "scene.png").string(), sceneImage(200, 150));
  auto s = std::make_unique<ui::AppState>();
  s->worker.setSynchronous(true);
  s->autoSpacing = false;
  s->bindParams.spacing = 10.0;
  EXPECT_TRUE(ui::openImage(*s, (dir / "scene.png").string()));
  return s;
}

/// Opens `path` as File > Open does; the newest message afterwards.
std::string open(ui::AppState& s, const fs::path& path) {
  ui::openAnyFile(s, path.string());
  ui::pollWorker(s);
  return s.messages.empty() ? std::string() : s.messages.back().text;
}

TEST(OpenFiles, ACageWithAMistakeIsRefusedAsACageAndOtherJsonAsASession) {
  const fs::path dir = scratchDir("ui_open_files");
  auto s = pictureDocument(dir);
  const std::string picture = s->imagePath;
  auto expectUntouched = [&](const std::string& message) {
    EXPECT_TRUE(s->messages.back().error) << message;
    EXPECT_EQ(s->imagePath, picture) << message;
    EXPECT_EQ(s->source.width, 200) << message;
    EXPECT_FALSE(s->session) << message;
    EXPECT_EQ(s->cage.size(), 0) << message;
  };

  writeText(dir / "far.json", R"({"version":1,"points":[[10,10],[1e300,10],[50,50]],"closed":true})");
  std::string m = open(*s, dir / "far.json");
  EXPECT_EQ(m.rfind("Cannot load cage: ", 0), 0u) << m;
  EXPECT_NE(m.find("far.json: points[1][0] = 1e+300 is out of range"), std::string::npos) << m;
  expectUntouched(m);

  writeText(dir / "cut.json", R"({"version": 1, "points": [[10,10],[90,10],[90,)");
  m = open(*s, dir / "cut.json");
  EXPECT_EQ(m.rfind("Cannot load cage: ", 0), 0u) << m;
  EXPECT_NE(m.find("cut.json: malformed JSON"), std::string::npos) << m;
  expectUntouched(m);

  // A pose file has no points: not a cage, and as a session it names what is missing.
  writeText(dir / "pose.json", R"({"version":1,"handles":[{"translate":[0,0],"rotate":0}]})");
  m = open(*s, dir / "pose.json");
  EXPECT_EQ(m.rfind("Cannot open session: ", 0), 0u) << m;
  EXPECT_NE(m.find("pose.json: "), std::string::npos) << m;
  expectUntouched(m);

  // A session saved under a plain .json name still opens as one.
  writeText(dir / "cage.json", R"({"version": 1, "points": [[40,30],[160,30],[160,120],[40,120]], "closed": true})");
  const CliResult bound = runCli("bind --cage cage.json --image scene.png --spacing 10 -o session.json", dir);
  ASSERT_EQ(bound.code, 0) << bound.err;
  m = open(*s, dir / "session.json");
  ASSERT_TRUE(s->session) << m;
  EXPECT_EQ(s->sessionPath, (dir / "session.json").string());
}

TEST(OpenFiles, OutOfMemoryNamesTheFileAndOtherFailuresKeepTheirMessage) {
  EXPECT_EQ(ui::failureText(std::bad_alloc(), "/tmp/x.kcw.json", "opening it needs more memory than is free"),
            "/tmp/x.kcw.json: out of memory: opening it needs more memory than is free");
  EXPECT_EQ(ui::failureText(std::bad_alloc(), "", "use a larger spacing"), "out of memory: use a larger spacing");
  const app::InputError bad("/tmp/y.json", "missing key 'points'");
  EXPECT_EQ(ui::failureText(bad, "/tmp/y.json", "unused"), "/tmp/y.json: missing key 'points'");
}

}  // namespace
}  // namespace kc::test
