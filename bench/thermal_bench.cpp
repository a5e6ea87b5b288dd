// The thermal model's cost (docs/performance.md, "Heat"): deposit() per 1 kHz step, and
// diffuse() per visual frame (1/60 s) on the built-in humerus's box at 0.5 mm cells, with the
// heat of a 2 s drilling near the tip, and with every cell active (the worst case).
#include <benchmark/benchmark.h>

#include "osteon/simulation/session.h"
#include "osteon/simulation/thermal.h"

namespace {

using namespace osteon::simulation;

const osteon::geometry::VoxelGrid& humerus() {
  static const auto bone = BoneModel::open("default", 1.0, 1.2);
  return bone->grid();
}

HeatInput cut(const glm::dvec3& tipMm) {
  HeatInput in;
  in.tipMm = tipMm;
  in.removedMm3 = 0.012;
  in.rhoGcm3 = 1.85;
  in.rpm = 1140.0;
  in.diameterMm = 3.2;
  in.thrustN = 150.0;
  in.cutting = true;
  return in;
}

glm::dvec3 centre(const ThermalModel& m) {
  return m.originMm() + 0.5 * glm::dvec3(m.dims()) * m.cellMm();
}

void BM_ThermalDeposit(benchmark::State& state) {
  ThermalModel m(humerus(), ThermalOptions{});
  const HeatInput in = cut(centre(m));
  int n = 0;
  for (auto _ : state) {
    m.deposit(in);
    if (++n % 500 == 0) {  // the visual thread drains what the ring holds, untimed
      state.PauseTiming();
      m.diffuse(0.0);
      state.ResumeTiming();
    }
  }
}
BENCHMARK(BM_ThermalDeposit);

void BM_ThermalDiffuseNearTip(benchmark::State& state) {
  ThermalModel m(humerus(), ThermalOptions{});
  const glm::dvec3 c = centre(m);
  // state.range(0) seconds of drilling 2 mm/s down, diffused at 60 Hz, before the timed frames.
  for (int step = 0; step < 1000 * int(state.range(0)); ++step) {
    m.deposit(cut(c - glm::dvec3(0.0, 0.0, 0.002 * step)));
    if (step % 17 == 16) m.diffuse(1.0 / 60.0);
  }
  for (auto _ : state) m.diffuse(1.0 / 60.0);
  state.counters["cells"] = double(m.dims().x) * m.dims().y * m.dims().z;
  state.counters["cell_mm"] = m.cellMm();
}
BENCHMARK(BM_ThermalDiffuseNearTip)->Arg(2)->Arg(10)->Unit(benchmark::kMillisecond)->Iterations(60);

void BM_ThermalDiffuseWholeGrid(benchmark::State& state) {
  ThermalModel m(humerus(), ThermalOptions{});
  // Heat at two opposite corners: the active box spans the grid.
  m.deposit(cut(m.originMm() + m.cellMm()));
  m.deposit(cut(m.originMm() + (glm::dvec3(m.dims()) - 1.0) * m.cellMm()));
  for (auto _ : state) m.diffuse(1.0 / 60.0);
  state.counters["cells"] = double(m.dims().x) * m.dims().y * m.dims().z;
  state.counters["cell_mm"] = m.cellMm();
}
BENCHMARK(BM_ThermalDiffuseWholeGrid)->Unit(benchmark::kMillisecond)->Iterations(20);

}  // namespace

BENCHMARK_MAIN();
