// The thermal model's 1 kHz side allocates nothing: deposit() with the ring filling, full and
// merging, and while diffuse() drains it. Its own program's allocation counter sees every heap
// allocation (support/allocation_counter.cpp).
#include <cstdint>

#include <gtest/gtest.h>

#include "osteon/simulation/thermal.h"
#include "support/allocation_counter.h"

namespace osteon::simulation {
namespace {

TEST(ThermalAllocation, DepositAllocatesNothing) {
  const std::uint64_t beforeSetUp = test::allocations();
  ThermalModel m(glm::dvec3(0.0), glm::dvec3(20.0), ThermalOptions{});
  EXPECT_GT(test::allocations(), beforeSetUp);  // the count does see the set-up's allocations
  HeatInput in;
  in.removedMm3 = 0.012;
  in.rhoGcm3 = 1.85;
  in.rpm = 1140.0;
  in.diameterMm = 3.2;
  in.thrustN = 150.0;
  in.cutting = true;
  std::uint64_t inDeposits = 0;
  // 3 s at 1 kHz: diffused at 100 Hz for the first second, then not at all (the ring fills and
  // steps merge), then again.
  for (int step = 0; step < 3000; ++step) {
    in.tipMm = glm::dvec3(10.0, 10.0, 15.0 - 0.002 * step);
    in.irrigation = step % 500 < 250;
    const std::uint64_t before = test::allocations();
    m.deposit(in);
    inDeposits += test::allocations() - before;
    if ((step < 1000 || step >= 2500) && step % 10 == 9) m.diffuse(0.01);
  }
  EXPECT_EQ(inDeposits, 0u);
  EXPECT_GT(m.mergedDeposits(), 0u);
  EXPECT_GT(m.tipTemperatureC(), 37.0);
}

}  // namespace
}  // namespace osteon::simulation
