// OSTEON_ASSERT under NDEBUG: compiled out, its condition never evaluated.
#ifndef NDEBUG
#define NDEBUG
#endif
#include <gtest/gtest.h>

#include "osteon/core/assert.h"

namespace osteon {
namespace {

TEST(Assert, AReleaseBuildNeitherChecksNorEvaluates) {
  int evaluated = 0;
  OSTEON_ASSERT(++evaluated == 42, "never checked");
  EXPECT_EQ(evaluated, 0);
}

}  // namespace
}  // namespace osteon
