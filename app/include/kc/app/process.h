#pragma once
/// Process-level set-up shared by kcwarp and kcwarp-cli.

namespace kc::app {

/// Makes OpenMP threads sleep, not spin, while they wait: with spinning, a busy machine (or the
/// GUI's render thread next to a bind) makes parallel loops many times slower. libgomp reads
/// OMP_WAIT_POLICY only when it loads, so when the variable is unset this sets it and re-executes
/// the program once with the same arguments. Returns normally when nothing needed doing or the
/// re-execution failed. Call first thing in main().
void preferPassiveOpenMpWaiting(char** argv);

/// Memory kept aside by keepMemoryReserve, bytes (64 MiB).
inline constexpr unsigned long kMemoryReserveBytes = 64ul * 1024 * 1024;
/// Sets aside kMemoryReserveBytes (address space, not touched) and installs a new-handler that,
/// on the first allocation that fails, frees it and throws std::bad_alloc: the destructors that
/// run while that exception unwinds (nlohmann::json's allocates its work stack) then find memory
/// instead of throwing a second std::bad_alloc, which would end the program (std::terminate).
/// Later failures throw std::bad_alloc at once, until this is called again: a program that carries
/// on after a std::bad_alloc (the GUI, after a load that did not fit) calls it once the failure was
/// handled to set the reserve aside anew (nothing happens while the reserve is in place, or when
/// the memory for it is not free). Call early in main().
void keepMemoryReserve();

}  // namespace kc::app
