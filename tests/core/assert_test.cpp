// OSTEON_ASSERT as a debug build has it, whatever this test program's own build type.
#undef NDEBUG
#include "osteon/core/assert.h"

#include <gtest/gtest.h>

namespace osteon {
namespace {

TEST(Assert, ADebugBuildAbortsWithOneLineNamingTheInvariant) {
  int checked = 0;
  OSTEON_ASSERT(++checked == 1, "evaluated once");
  EXPECT_EQ(checked, 1);
  EXPECT_DEATH(OSTEON_ASSERT(checked == 2, "the count is two"),
               "^osteon: internal error: .*assert_test.cpp:[0-9]+: the count is two \\(assertion "
               "checked == 2 failed\\)");
}

}  // namespace
}  // namespace osteon
