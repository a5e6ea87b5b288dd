#include "osteon/validation/validate.h"

#include <gtest/gtest.h>

namespace osteon::validation {
namespace {

// The verdict follows the crack-free cases only: the naive baseline is expected to fail.
TEST(ValidationReport, VerdictFollowsTheCrackFreeCases) {
  ValidationReport report;
  ValidationCase naive;
  naive.method = geometry::SurfaceMethod::Naive;
  naive.failures.push_back("before drilling: 12 border edges");
  ValidationCase crackFree;
  crackFree.method = geometry::SurfaceMethod::CrackFree;
  report.cases = {naive, crackFree};
  EXPECT_TRUE(report.pass());
  report.cases[1].failures.push_back("portal-5: 1 collision misses");
  EXPECT_FALSE(report.pass());
  EXPECT_FALSE(report.cases[1].pass());
}

}  // namespace
}  // namespace osteon::validation
