// The calibrated cutting resistance (cutting.h): its constants are the fit of the published
// rows, its residuals stay within what the rows' scatter allows, the ratios a trainee should
// feel hold, and the feed law is the thrust law's inverse.
#include "osteon/simulation/cutting.h"

#include <cmath>

#include <gtest/gtest.h>

#include "osteon/core/option_error.h"

namespace osteon::simulation {
namespace {

TEST(Cutting, TheConstantsAreTheFitOfThePublishedRows) {
  const ThrustFit fit = fitThrustModel(publishedThrustRows());
  const ThrustModel shipped;
  EXPECT_NEAR(fit.model.alpha, shipped.alpha, 1e-4);
  EXPECT_NEAR(fit.model.kNPerGcm3, shipped.kNPerGcm3, 0.01);
  EXPECT_NEAR(fit.model.rho0Gcm3, shipped.rho0Gcm3, 1e-4);
  ASSERT_EQ(fit.residual.size(), publishedThrustRows().size());
  for (std::size_t i = 0; i < fit.residual.size(); ++i)
    EXPECT_LT(std::abs(fit.residual[i]), 0.15) << publishedThrustRows()[i].material;
  // Human cortical bone at the reference renders as 3.0 N.
  EXPECT_NEAR(kDeviceNPerRealN * shipped.thrustN(kCorticalGcm3, 3.2, 2.0, 1000.0), 3.0, 0.01);
}

TEST(Cutting, CortexResistsMoreSlowRpmMoreFastFeedMore) {
  const ThrustModel m;
  EXPECT_GT(m.thrustN(kCorticalGcm3, 3.2, 2, 1000), 50 * m.thrustN(kCancellousGcm3, 3.2, 2, 1000));
  EXPECT_GT(m.thrustN(kCorticalGcm3, 3.2, 2, 1000), m.thrustN(kCorticalGcm3, 3.2, 2, 1500));
  EXPECT_GT(m.thrustN(kCorticalGcm3, 3.2, 3, 1000), m.thrustN(kCorticalGcm3, 3.2, 2, 1000));
  EXPECT_GT(m.thrustN(kCorticalGcm3, 4.5, 2, 1000), m.thrustN(kCorticalGcm3, 3.2, 2, 1000));
  EXPECT_EQ(m.thrustN(0.2, 3.2, 2, 1000), 0.0);  // below rho0: crumbles
  EXPECT_EQ(m.thrustN(kCorticalGcm3, 3.2, 0, 1000), 0.0);
}

TEST(Cutting, TheFeedLawInvertsTheThrustLaw) {
  const ThrustModel m;
  for (const double feed : {0.3, 1.0, 2.0, 5.0}) {
    for (const double rpm : {800.0, 1250.0, 20000.0}) {
      const double f = m.thrustN(1.2, 2.5, feed, rpm);
      EXPECT_NEAR(m.feedMmPerS(f, 1.2, 2.5, rpm), feed, 1e-9 * feed);
    }
  }
  EXPECT_TRUE(std::isinf(m.feedMmPerS(1.0, 0.1, 3.2, 1000)));
  EXPECT_EQ(m.feedMmPerS(0.0, 1.5, 3.2, 1000), 0.0);
}

TEST(Cutting, DensityMapsTheSeedsMaterialsAndOptionsAreChecked) {
  EXPECT_DOUBLE_EQ(apparentDensityGcm3(40), kCorticalGcm3);
  EXPECT_DOUBLE_EQ(apparentDensityGcm3(15), kCancellousGcm3);
  EXPECT_GE(apparentDensityGcm3(1), 0.05);
  EXPECT_EQ(parseForceModelKind("seed"), ForceModelKind::Seed);
  EXPECT_EQ(parseForceModelKind("calibrated"), ForceModelKind::Calibrated);
  EXPECT_THROW(parseForceModelKind("real"), OptionError);
  EXPECT_THROW(validateRpm(50), OptionError);
  EXPECT_THROW(validateRpm(NAN), OptionError);
  EXPECT_NO_THROW(validateRpm(1000));
}

}  // namespace
}  // namespace osteon::simulation
