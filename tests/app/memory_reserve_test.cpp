// The memory reserve (kc::app::keepMemoryReserve): the first allocation that fails frees it and
// throws std::bad_alloc; calling keepMemoryReserve again sets it aside anew, so a program that
// carries on after a failure (the GUI) has it for the next one. Run in a child process whose
// address space is limited (RLIMIT_AS), which the sanitizers' shadow memory does not allow.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fstream>
#include <new>
#include <string>
#include <vector>

#include "kc/app/process.h"

namespace kc::app {
namespace {

/// This process's address space (VmSize), bytes.
std::uint64_t addressSpace() {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("VmSize:", 0) == 0) return std::stoull(line.substr(7)) * 1024;
  return 0;
}

/// In the child: 0 when an allocation beyond the limit throws std::bad_alloc, which frees the
/// reserve (the address space shrinks by it), and keepMemoryReserve sets it aside again; a
/// positive code naming the step that did not hold.
int reserveCycle() {
  const std::uint64_t before = addressSpace();
  try {
    std::vector<char> tooLarge(std::size_t(1) << 30);  // 1 GiB: more than the limit leaves
    return 1;
  } catch (const std::bad_alloc&) {
  }
  const std::uint64_t freed = addressSpace();
  if (freed + kMemoryReserveBytes > before) return 2;
  keepMemoryReserve();
  if (addressSpace() < freed + kMemoryReserveBytes) return 3;
  return 0;
}

TEST(MemoryReserve, AFailedAllocationFreesItAndItCanBeSetAsideAgain) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "the address space cannot be limited under AddressSanitizer";
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
  GTEST_SKIP() << "the address space cannot be limited under AddressSanitizer";
#endif
#endif
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    keepMemoryReserve();
    const std::uint64_t used = addressSpace();
    const rlimit limit{used + (256ull << 20), used + (256ull << 20)};
    if (used == 0 || setrlimit(RLIMIT_AS, &limit) != 0) _exit(10);
    for (int k = 0; k < 3; ++k)  // each failure finds the reserve set aside again
      if (const int step = reserveCycle(); step != 0) _exit(10 * (k + 1) + step);
    _exit(0);
  }
  int status = 0;
  ASSERT_EQ(waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFEXITED(status)) << "the child ended by signal " << WTERMSIG(status);
  EXPECT_EQ(WEXITSTATUS(status), 0) << "10: no address-space limit; 10k+1: no bad_alloc; 10k+2: the reserve was not freed; "
                                       "10k+3: it was not set aside again (k: the attempt)";
}

}  // namespace
}  // namespace kc::app
