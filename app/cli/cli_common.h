#pragma once
// Shared pieces of kcwarp-cli: exit codes, subcommand registration, small argument helpers.

#include <CLI/CLI.hpp>
#include <string>
#include <vector>
#include <utility>

#include "kc/core/warp_mesh.h"
#include "kc/app/errors.h"
#include "kc/core/names.h"

namespace kc::cli {

/// Exit codes (ARCHITECTURE.md): 0 success, 1 internal failure, 2 bad input (one line on stderr).
inline constexpr int kExitOk = 0;
inline constexpr int kExitInternal = 1;
inline constexpr int kExitBadInput = 2;

// One function per subcommand, each in its own cli_<name>.cpp: adds the subcommand and its
// callback (which throws kc::app::InputError on bad input).
void addSampleCommand(CLI::App& app);
void addBindCommand(CLI::App& app);
void addEvalCommand(CLI::App& app);
void addWarpCommand(CLI::App& app);
void addStatsCommand(CLI::App& app);
void addDemoCommand(CLI::App& app);
void addBenchCommand(CLI::App& app);

/// The value of the named enum E called `text` (kc/core/names.h); InputError naming `option`
/// and the accepted names otherwise.
template <NamedEnum E>
E parseOption(const std::string& text, const char* option) {
  E e{};
  if (!parseName(text, e)) throw app::InputError(option, "unknown value '" + text + "' (accepted: " + nameList<E>() + ")");
  return e;
}

/// The name of a named enum's value as a std::string (option defaults, printed tables).
template <NamedEnum E>
std::string nameOf(E value) {
  return std::string(toString(value));
}

/// "W,H" → (W, H); InputError naming `option` when malformed or not positive.
std::pair<int, int> parseSize(const std::string& text, const std::string& option);
/// Width and height of an image file as loadImage lays it out (upright); InputError naming the file
/// when it cannot be read.
std::pair<int, int> imageSize(const std::string& path);
/// Width and height from the image file's header (format and limits checked, pixels not decoded),
/// upright (ImageHeader::uprightWidth): what `bind` needs of a picture.
std::pair<int, int> imageHeaderSize(const std::string& path);
/// InputError naming `option` when `value` is NaN or infinite ("must be a finite number of `unit`";
/// no unit for an empty one).
void requireFinite(double value, const std::string& option, const std::string& unit = "pixels");
/// The limits kcwarp puts on its input (kc/app/limits.h), as the footer of `--help`.
std::string limitsText();

/// The middle value of `v` (the upper one of the two middle values for an even count); 0 when empty.
double median(std::vector<double> v);
/// Help text of the --outside options.
inline constexpr const char* kOutsideHelp =
    "Outside the cage: pinned (the image border stays, the background between cage and border stretches) | "
    "deform (the weights move everything, the thesis) | fixed (only the inside moves, drawn over the picture) | "
    "transparent (only the inside is drawn)";
/// Adds `--png-compression 0..9` (zlib level of the PNGs written; default
/// app::kDefaultPngCompression, fast) to a subcommand; a value outside 0..9 is a parse error (exit 2).
void addPngCompressionOption(CLI::App* sub, int& level);
/// CLI11 check of a `--seed`: a whole decimal number 0..2^64-1 (CLI11 alone reads "-1" as 2^64-1
/// and a number past 2^64-1 as 2^64-1); anything else is a parse error (exit 2).
CLI::Validator seedCheck();
/// True when stderr is a terminal (progress output is shown only then).
bool stderrIsTerminal();

}  // namespace kc::cli
