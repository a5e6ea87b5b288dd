// The thermal model: CEM43 dose, conservation of heat by conduction, irrigation's cooling, the
// deposit's hand-over and the options' checks.
#include "osteon/simulation/thermal.h"

#include <atomic>
#include <cmath>
#include <thread>

#include <gtest/gtest.h>

#include "osteon/core/option_error.h"

namespace osteon::simulation {
namespace {

ThermalOptions smallGrid() {
  ThermalOptions o;
  o.cellMm = 0.5;
  o.marginMm = 0.0;
  return o;
}

HeatInput cutAt(const glm::dvec3& tipMm, bool irrigation) {
  HeatInput in;
  in.tipMm = tipMm;
  in.removedMm3 = 0.01;  // 10 mm3/s at 1 kHz
  in.rhoGcm3 = 1.85;
  in.rpm = 1820.0;
  in.diameterMm = 4.5;
  in.thrustN = 120.0;
  in.irrigation = irrigation;
  in.cutting = true;
  return in;
}

TEST(Thermal, Cem43OfFortySevenForAMinuteIsSixteen) {
  EXPECT_NEAR(cem43Minutes(47.0, 60.0), 16.0, 1e-12);
  EXPECT_NEAR(cem43Minutes(43.0, 60.0), 1.0, 1e-12);
  EXPECT_NEAR(cem43Minutes(41.0, 60.0), 1.0 / 16.0, 1e-12);  // R = 0.25 below 43 °C
  // Held in the grid: a block uniformly at 47 °C (faces held there too) for 60 s.
  ThermalOptions o = smallGrid();
  o.initialC = 47.0;
  ThermalModel m(glm::dvec3(0.0), glm::dvec3(2.0), o);
  HeatInput nothing;  // a deposit of no heat, so the model's cells are active
  nothing.tipMm = glm::dvec3(1.0);
  m.deposit(nothing);
  for (int i = 0; i < 60; ++i) m.diffuse(1.0);
  EXPECT_NEAR(m.doseAtMin(glm::dvec3(1.0)), 16.0, 1e-3);
  EXPECT_GT(m.damagedVolumeMm3(), 0.0);
  EXPECT_NEAR(m.peakC(), 47.0, 1e-9);
}

TEST(Thermal, DamagedBoneCountsOnlyTheBoneLeft) {
  // A 4 mm cube of bone, one half drilled away; the box around it held at 47 °C for 61 s.
  geometry::VoxelGrid bone(glm::ivec3(8), glm::dvec3(0.0), 0.5);
  for (int k = 0; k < 8; ++k)
    for (int j = 0; j < 8; ++j)
      for (int i = 0; i < 8; ++i) bone.set({i, j, k}, i < 4 ? geometry::kFillFull : 0, 40);
  ThermalOptions o = smallGrid();
  o.initialC = 47.0;
  ThermalModel m(bone, o);
  for (int i = 0; i < 61; ++i) m.diffuse(1.0);
  EXPECT_NEAR(m.damagedVolumeMm3(), 64.0, 1e-9);
  EXPECT_NEAR(m.damagedBoneVolumeMm3(bone), 32.0, 1e-9);
  // The viewer's samples at surface vertices read the same temperature.
  const glm::vec3 points[2] = {glm::vec3(1.0f), glm::vec3(3.0f, 2.0f, 2.0f)};
  float sampled[2] = {0.0f, 0.0f};
  m.sampleC(points, 2, sampled);
  EXPECT_FLOAT_EQ(sampled[0], 47.0f);
  EXPECT_FLOAT_EQ(sampled[1], 47.0f);
}

TEST(Thermal, DamageNeedsTheDose) {
  ThermalOptions o = smallGrid();
  o.initialC = 46.0;  // 46 °C for a minute: 8 CEM43-min, short of 16
  ThermalModel m(glm::dvec3(0.0), glm::dvec3(2.0), o);
  HeatInput nothing;
  nothing.tipMm = glm::dvec3(1.0);
  m.deposit(nothing);
  for (int i = 0; i < 60; ++i) m.diffuse(1.0);
  EXPECT_NEAR(m.doseAtMin(glm::dvec3(1.0)), 8.0, 1e-3);
  EXPECT_EQ(m.damagedVolumeMm3(), 0.0);
}

TEST(Thermal, ConductionConservesHeatAwayFromTheFaces) {
  ThermalModel m(glm::dvec3(0.0), glm::dvec3(20.0), smallGrid());
  for (int i = 0; i < 500; ++i) m.deposit(cutAt(glm::dvec3(10.0), false));
  m.diffuse(0.0);  // drained, not yet conducted
  const double deposited = m.depositedJ();
  ASSERT_GT(deposited, 1.0);
  EXPECT_NEAR(m.heatContentJ(), deposited, 1e-9 * deposited);
  const double hot = m.temperatureAtC(glm::dvec3(10.0));
  const glm::vec3 tip(10.0f);
  float sampled = 0.0f;
  m.sampleC(&tip, 1, &sampled);
  EXPECT_FLOAT_EQ(sampled, float(hot));
  for (int i = 0; i < 100; ++i) m.diffuse(0.02);  // 2 s: the heat spreads ~1 mm, far from faces
  // (to the trace the active box leaves behind: cells within 1e-6 K of 37 °C rest)
  EXPECT_NEAR(m.heatContentJ(), deposited, 1e-6 * deposited);
  EXPECT_LT(m.temperatureAtC(glm::dvec3(10.0)), hot);
  EXPECT_GT(m.temperatureAtC(glm::dvec3(11.5, 10.0, 10.0)), 37.0);
  // Long enough, the held faces take the heat out.
  for (int i = 0; i < 200; ++i) m.diffuse(1.0);
  EXPECT_LT(m.heatContentJ(), 0.5 * deposited);
}

TEST(Thermal, SubSteppedConductionMatchesFineSteps) {
  // One call of 0.5 s (sub-stepped) against fifty of 10 ms: the same heat and nearly the
  // same temperatures.
  ThermalModel coarse(glm::dvec3(0.0), glm::dvec3(10.0), smallGrid());
  ThermalModel fine(glm::dvec3(0.0), glm::dvec3(10.0), smallGrid());
  for (int i = 0; i < 200; ++i) {
    coarse.deposit(cutAt(glm::dvec3(5.0), false));
    fine.deposit(cutAt(glm::dvec3(5.0), false));
  }
  coarse.diffuse(0.5);
  for (int i = 0; i < 50; ++i) fine.diffuse(0.01);
  // (explicit steps reach a cell further each: fifty reach the faces, with a trace of heat)
  EXPECT_NEAR(coarse.heatContentJ(), fine.heatContentJ(), 1e-6 * fine.heatContentJ());
  const glm::dvec3 p(6.0, 5.0, 5.0);
  EXPECT_NEAR(coarse.temperatureAtC(p), fine.temperatureAtC(p),
              0.1 * (fine.temperatureAtC(p) - 37.0));
  EXPECT_TRUE(std::isfinite(coarse.peakC()));
}

TEST(Thermal, IrrigationLowersThePeak) {
  double peaks[2] = {0.0, 0.0};
  for (const bool irrigation : {false, true}) {
    ThermalModel m(glm::dvec3(0.0), glm::dvec3(20.0), smallGrid());
    for (int step = 0; step < 3000; ++step) {
      m.deposit(cutAt(glm::dvec3(10.0, 10.0, 15.0 - 0.002 * step), irrigation));
      if (step % 10 == 9) m.diffuse(0.01);
    }
    peaks[irrigation] = m.peakAtC(glm::dvec3(12.5, 10.0, 12.0));
    EXPECT_GT(m.tipTemperatureC(), irrigation ? 26.0 : 37.0);
    EXPECT_EQ(m.mergedDeposits(), 0u);
  }
  EXPECT_GT(peaks[0], 40.0);
  EXPECT_LT(peaks[1], peaks[0] - 2.0);
}

TEST(Thermal, AFullRingMergesStepsWithoutLosingHeat) {
  ThermalModel m(glm::dvec3(0.0), glm::dvec3(10.0), smallGrid());
  const HeatInput in = cutAt(glm::dvec3(5.0), false);
  for (int i = 0; i < 3000; ++i) m.deposit(in);  // 3 s with no consumer
  EXPECT_GT(m.mergedDeposits(), 0u);
  m.diffuse(0.0);  // drains the ring
  m.deposit(in);   // the merged steps go out with the next push
  m.diffuse(0.0);
  const double perStep = in.dtS * m.options().cutting.heatFraction *
                         m.options().cutting.powerW(in.removedMm3 / in.dtS, in.rhoGcm3, in.rpm,
                                                    in.diameterMm, in.thrustN);
  EXPECT_NEAR(m.depositedJ(), 3001.0 * perStep, 1e-9 * 3001.0 * perStep);
}

TEST(Thermal, ProducerAndConsumerThreadsLoseNoHeat) {
  // The 1 kHz side deposits on its thread while the visual side diffuses on another, reading
  // the tip temperature as a log would: every step's heat arrives.
  ThermalModel m(glm::dvec3(0.0), glm::dvec3(20.0), smallGrid());
  const HeatInput in = cutAt(glm::dvec3(10.0), false);
  constexpr int kSteps = 20000;
  std::atomic<bool> done{false};
  double tipSeen = 0.0;
  std::thread producer([&] {
    for (int i = 0; i < kSteps; ++i) {
      m.deposit(in);
      tipSeen = std::max(tipSeen, m.tipTemperatureC());
    }
    done.store(true);
  });
  while (!done.load()) m.diffuse(0.001);
  producer.join();
  m.diffuse(0.0);                  // drains the ring
  m.deposit(HeatInput{in.tipMm});  // a step of no heat carries a merged remainder out
  m.diffuse(0.0);
  const double perStep = in.dtS * m.options().cutting.heatFraction *
                         m.options().cutting.powerW(in.removedMm3 / in.dtS, in.rhoGcm3, in.rpm,
                                                    in.diameterMm, in.thrustN);
  EXPECT_NEAR(m.depositedJ(), kSteps * perStep, 1e-9 * kSteps * perStep);
  EXPECT_GE(tipSeen, 37.0);
}

TEST(Thermal, CuttingPowerGrowsWithRpmThrustAndRemoval) {
  const CuttingHeatModel c;
  const double base = c.powerW(10.0, 1.85, 1000.0, 3.2, 100.0);
  EXPECT_GT(c.powerW(10.0, 1.85, 1800.0, 3.2, 100.0), base);
  EXPECT_GT(c.powerW(10.0, 1.85, 1000.0, 3.2, 150.0), base);
  EXPECT_GT(c.powerW(20.0, 1.85, 1000.0, 3.2, 100.0), base);
  EXPECT_LT(c.powerW(10.0, 0.30, 1000.0, 3.2, 100.0), base);
  EXPECT_EQ(c.powerW(0.0, 1.85, 1000.0, 3.2, 0.0), 0.0);
}

TEST(Thermal, LargeBoxesGetLargerCells) {
  ThermalOptions o;
  o.maxCells = 100000;
  ThermalModel m(glm::dvec3(0.0), glm::dvec3(100.0), o);
  EXPECT_GT(m.cellMm(), o.cellMm);
  EXPECT_LE(std::size_t(m.dims().x) * std::size_t(m.dims().y) * std::size_t(m.dims().z),
            o.maxCells);
}

TEST(Thermal, RefusesBadOptions) {
  ThermalOptions o;
  o.cellMm = 0.0;
  EXPECT_THROW(validateThermalOptions(o), OptionError);
  o = ThermalOptions{};
  o.cutting.heatFraction = 1.5;
  EXPECT_THROW(validateThermalOptions(o), OptionError);
  o = ThermalOptions{};
  o.bone.conductivityWPerMK = -0.4;
  try {
    ThermalModel m(glm::dvec3(0.0), glm::dvec3(1.0), o);
    FAIL() << "accepted a negative conductivity";
  } catch (const OptionError& e) {
    EXPECT_EQ(e.field(), "thermal.bone.conductivityWPerMK");
  }
}

}  // namespace
}  // namespace osteon::simulation
