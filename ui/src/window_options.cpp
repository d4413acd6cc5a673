#include <cstdio>
#include <cstdlib>
#include <string>

#include "kc/ui/window.h"

namespace kc::ui {

const char* usageText() {
  return "usage: kcwarp [IMAGE.png|SESSION.kcw.json] [--cage CAGE.json] [--export OUT.png]\n"
         "              [--ready-file F] [--frame-log F.csv] [--screenshot-dir DIR] [--recovery F] [--size WxH] [--spacing H]\n"
         "              [--slow-frames MS]\n"
         "Without INPUT the bundled figure example opens, already bound.\n";
}

WindowOptions parseWindowOptions(int argc, char** argv) {
  WindowOptions o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&](std::string& out) {
      if (i + 1 >= argc) {
        o.error = a + " needs a value";
        return;
      }
      out = argv[++i];
    };
    if (a == "-h" || a == "--help") o.help = true;
    else if (a == "--cage") value(o.cage);
    else if (a == "--ready-file") value(o.readyFile);
    else if (a == "--frame-log") value(o.frameLog);
    else if (a == "--screenshot-dir") value(o.screenshotDir);
    else if (a == "--export") value(o.exportPath);
    else if (a == "--recovery") value(o.recoveryPath);
    else if (a == "--examples") value(o.examplesDir);
    else if (a == "--spacing") {
      std::string s;
      value(s);
      o.spacing = std::atof(s.c_str());
      if (!(o.spacing > 0.0)) o.error = "--spacing expects a positive number of pixels";
    } else if (a == "--slow-frames") {
      std::string s;
      value(s);
      o.slowFramesMs = std::atoi(s.c_str());
      if (o.slowFramesMs <= 0) o.error = "--slow-frames expects a positive number of milliseconds";
    } else if (a == "--size") {
      std::string s;
      value(s);
      if (std::sscanf(s.c_str(), "%dx%d", &o.width, &o.height) != 2 || o.width < 320 || o.height < 240)
        o.error = "--size expects WxH (at least 320x240), got '" + s + "'";
    } else if (!a.empty() && a[0] == '-') o.error = "unknown option " + a;
    else if (o.input.empty()) o.input = a;
    else o.error = "more than one input file given";
    if (!o.error.empty()) break;
  }
  return o;
}

}  // namespace kc::ui
