#include "kc/ui/document.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "kc/app/file_io.h"
#include "ui_fixture.h"

namespace kc::test {
namespace {

TEST(Recovery, AutosaveWritesALoadableCopyAndANormalQuitRemovesIt) {
  auto state = boundState();
  const auto dir = std::filesystem::temp_directory_path() / "kcwarp_test_recovery";
  std::filesystem::remove_all(dir);
  state->recoveryPath = (dir / "recovery.kcw.json").string();
  state->lastAutosave = 0.0;

  state->unsaved = false;
  EXPECT_FALSE(ui::maybeAutosave(*state, 1000.0));  // nothing unsaved: nothing written
  EXPECT_FALSE(ui::hasRecoveryCopy(*state));

  state->unsaved = true;
  EXPECT_FALSE(ui::maybeAutosave(*state, 30.0));    // less than a minute since the last one
  EXPECT_TRUE(ui::maybeAutosave(*state, 61.0));
  ASSERT_TRUE(ui::hasRecoveryCopy(*state));
  const app::Session copy = app::loadSession(state->recoveryPath);
  EXPECT_EQ(copy.W, state->session->W);
  EXPECT_EQ(copy.cage.C, state->session->cage.C);

  ui::discardRecoveryCopy(*state);
  EXPECT_FALSE(ui::hasRecoveryCopy(*state));
}

}  // namespace
}  // namespace kc::test
