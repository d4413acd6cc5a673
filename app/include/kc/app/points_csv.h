#pragma once
/// The points file of `kcwarp-cli eval`: "x,y" rows, an optional header line, blank lines skipped.

#include <string>

#include "kc/core/types.h"

namespace kc::app {

/// Parses CSV text into #P×2 points. The first line is a header only when neither of its fields
/// starts like a number ("x,y"); a first row such as "10,nan" is an error, not a header. Every
/// coordinate must be finite with |x| ≤ kMaxCoordinate. InputError naming `where` and the line.
Points parsePointsCsv(const std::string& text, const std::string& where);

/// readTextFile (at most kMaxPointsFileBytes) + parsePointsCsv.
Points loadPointsCsv(const std::string& path);

}  // namespace kc::app
