// kcwarp: the GUI (kc::ui). Parses the command line and runs the window.
#include <cstdio>

#include "kc/app/process.h"
#include "kc/ui/window.h"

int main(int argc, char** argv) {
  kc::app::preferPassiveOpenMpWaiting(argv);
  kc::app::keepMemoryReserve();  // a load or bind that runs out of memory is reported, and the window stays
  kc::ui::WindowOptions options = kc::ui::parseWindowOptions(argc, argv);
  if (options.help) {
    std::fputs(kc::ui::usageText(), stdout);
    return 0;
  }
  if (!options.error.empty()) {
    std::fprintf(stderr, "kcwarp: %s\n%s", options.error.c_str(), kc::ui::usageText());
    return 2;
  }
  if (options.examplesDir.empty()) options.examplesDir = KC_EXAMPLES_DIR;
  return kc::ui::runWindow(options);
}
