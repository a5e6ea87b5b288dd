// The trial recorder the viewer's haptic loop fills: no allocation within its capacity, and
// samples past it counted as dropped, not stored.
#include <gtest/gtest.h>

#include "osteon/simulation/score.h"
#include "support/allocation_counter.h"

namespace osteon::simulation {
namespace {

TEST(TrialRecorder, AddsWithoutAllocatingAndDropsPastItsCapacity) {
  TrialRecorder recorder(1000);
  HapticStep step;
  step.magnitudeN = 3.3;
  step.clamped = true;
  const std::uint64_t before = test::threadAllocations();
  for (int i = 0; i < 1200; ++i) recorder.add(0.001 * i, step, i % 2 == 0);
  EXPECT_EQ(test::threadAllocations(), before);
  ASSERT_EQ(recorder.samples().size(), 1000u);
  EXPECT_EQ(recorder.dropped(), 200u);
  EXPECT_TRUE(recorder.samples().back().clamped);
  EXPECT_FALSE(recorder.samples().back().drillOn);  // sample 999
  recorder.clear();
  EXPECT_TRUE(recorder.samples().empty());
  EXPECT_EQ(recorder.dropped(), 0u);
}

}  // namespace
}  // namespace osteon::simulation
