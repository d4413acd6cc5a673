#pragma once
/// kcwarp-cli's whole command line, for a main() (kcwarp-cli, or a test's CLI with a backend of its
/// own linked in). Header without CLI11, so that a main() compiles in no time.

namespace kc::cli {

/// Runs `kcwarp-cli argv[1..]`: guards the standard streams, sets the memory reserve aside, parses
/// and runs the subcommand. Returns the exit code (0 success, 2 bad input or usage, 1 internal
/// error; ARCHITECTURE.md, "Errors, exit codes, cancellation").
int runCli(int argc, char** argv);

}  // namespace kc::cli
