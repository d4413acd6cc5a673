#pragma once
/// Process-level set-up shared by kcwarp and kcwarp-cli.

namespace kc::app {

/// Makes OpenMP threads sleep, not spin, while they wait: with spinning, a busy machine (or the
/// GUI's render thread next to a bind) makes parallel loops many times slower. libgomp reads
/// OMP_WAIT_POLICY only when it loads, so when the variable is unset this sets it and re-executes
/// the program once with the same arguments. Returns normally when nothing needed doing or the
/// re-execution failed. Call first thing in main().
void preferPassiveOpenMpWaiting(char** argv);

}  // namespace kc::app
