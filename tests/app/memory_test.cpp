// core/memory.h: the pause of transparent huge pages during start-up.
#include "core/memory.h"

#include <gtest/gtest.h>

namespace voxgi {
namespace {

#if defined(__linux__)
// The pause is the process's own flag, which the kernel reports back: set while
// voxgi starts, cleared once it draws.
TEST(HugePages, PauseSetsAndClearsTheProcessFlag) {
  const int before = prctl(PR_GET_THP_DISABLE, 0, 0, 0, 0);
  ASSERT_GE(before, 0);
  pauseHugePages(true);
  EXPECT_EQ(prctl(PR_GET_THP_DISABLE, 0, 0, 0, 0), 1);
  pauseHugePages(false);
  EXPECT_EQ(prctl(PR_GET_THP_DISABLE, 0, 0, 0, 0), 0);
  pauseHugePages(before != 0);
}
#endif

}  // namespace
}  // namespace voxgi
