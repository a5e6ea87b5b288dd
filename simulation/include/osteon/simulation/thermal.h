// The heat of drilling in the bone near the tool (docs/feel.md, "Heat"): cutting power at the
// tip, conduction on a coarse grid, irrigation as a cooling term, and the thermal dose per cell.
//
// Power at the tip (per 1 kHz step):
//   P = u (rho / rho_cortical) Q  +  mu F v,        v = pi D rpm / 60 (the lips' surface speed)
// - u: the specific cutting energy per volume removed, roughly constant per material
//   (Arbabtafti et al. 2011; Jacobs et al. 1976 measure it for cortical bone), Q the removal
//   rate (mm3/s); scaled by the apparent density rho;
// - mu F v: friction at the cutting edges, growing with the real thrust F (N) and the rpm;
// - a fraction eta of P enters the bone; the rest leaves with the chips and the drill.
// Conduction: explicit finite differences on cells of cellMm (sub-stepped under the stability
// limit), cortical bone's constants; the grid's faces are held at the initial temperature.
// Irrigation: a convective loss h (T - T_water) through one cell face per cell, in a sphere
// around the tip (the water reaching the cutting zone), while irrigation is on.
// Dose: CEM43 (Sapareto & Dewey 1984), sum of dt R^(43 - T) with R = 0.5 at or above 43 °C,
// 0.25 below: 47 °C held 1 min gives 16 CEM43-min, the damage dose (Eriksson & Albrektsson 1983).
//
// Threads: one producer (the 1 kHz loop) calls deposit(); one consumer (the visual thread, or a
// deterministic driver) calls diffuse(), temperatureAtC() and sampleC(). deposit() hands each
// step's heat over through a lock-free ring (core/handoff.h), merging steps into one while the
// ring is full, so no heat is lost; it allocates, locks and throws nothing. tipTemperatureC(),
// peakC(), damagedVolumeMm3() and depositedJ() read atomics diffuse() publishes: any thread.
// The deterministic driver (runHeatExperiment) deposits every step and diffuses every 10 steps.
// Memory: every array is allocated by the constructor (at most maxCells cells, 24 bytes each:
// 50 MB at the default cap).
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include <glm/vec3.hpp>

#include "osteon/geometry/voxels/voxel_grid.h"

namespace osteon::simulation {

// Cortical bone (docs/feel.md): conductivity 0.3-0.55 W/(m K) in the literature.
struct BoneThermalConstants {
  double conductivityWPerMK = 0.4;
  double densityGcm3 = 1.85;
  double specificHeatJPerGK = 1.3;
  // Thermal diffusivity k / (rho c) in mm2/s.
  double diffusivityMm2PerS() const;
  // Heat capacity per volume, J/(mm3 K).
  double heatCapacityJPerMm3K() const;
};

// The cutting power model above; its constants fitted to Augustin et al. 2008 (docs/feel.md).
struct CuttingHeatModel {
  double specificEnergyJPerMm3 = 0.18;  // u, at cortical density
  double frictionCoefficient = 0.3;     // mu
  double heatFraction = 0.26;           // eta: the share of P that enters the bone
  // The power (W) generated at the tip, before eta.
  double powerW(double removedMm3PerS, double rhoGcm3, double rpm, double diameterMm,
                double thrustN) const noexcept;
};

struct ThermalOptions {
  double cellMm = 0.5;                          // the coarse grid's cell edge
  std::size_t maxCells = std::size_t(1) << 21;  // a larger box gets larger cells
  double marginMm = 2.0;                        // around the box given, so heat can leave the bone
  double initialC = 37.0;                       // body temperature: initial and on the grid's faces
  double irrigationC = 26.0;                    // the irrigation water (room temperature)
  double irrigationWPerM2K = 500.0;             // h, fitted (docs/feel.md)
  double irrigationReachMm = 1.0;               // the cooled sphere: drill radius + this
  double damageDoseMin = 16.0;                  // CEM43-min past which a cell counts as damaged
  BoneThermalConstants bone;
  CuttingHeatModel cutting;
};
// OptionError naming the thermal.* field unless every size and constant is positive and finite.
void validateThermalOptions(const ThermalOptions& options);

// One 1 kHz step's inputs to deposit().
struct HeatInput {
  glm::dvec3 tipMm{0.0};    // the drill tip's centre
  double removedMm3 = 0.0;  // bone removed this step
  double rhoGcm3 = 0.0;     // apparent density of the bone cut (apparentDensityGcm3)
  double rpm = 0.0;
  double diameterMm = 0.0;
  double thrustN = 0.0;  // real thrust (device N / kDeviceNPerRealN)
  bool irrigation = false;
  bool cutting = false;  // the drill is on and in bone: friction heats only then
  double dtS = 0.001;
};

class ThermalModel {
 public:
  // A box (mm) grown by marginMm, cells of cellMm or larger (maxCells). Throws OptionError
  // (validateThermalOptions) or InputError for an empty box. Allocates everything.
  ThermalModel(const glm::dvec3& loMm, const glm::dvec3& hiMm, const ThermalOptions& options);
  // The grid's box.
  ThermalModel(const geometry::VoxelGrid& grid, const ThermalOptions& options);
  ~ThermalModel();
  ThermalModel(const ThermalModel&) = delete;
  ThermalModel& operator=(const ThermalModel&) = delete;

  // Producer thread (1 kHz). Heat of one step into the ring. No allocation, lock or throw.
  void deposit(const HeatInput& input) noexcept;

  // Consumer thread. Drains the deposits, conducts dtS seconds (sub-stepped), cools, doses,
  // and publishes the tip temperature, the peak and the damaged volume.
  void diffuse(double dtS);

  // Consumer thread: trilinear temperature (°C) at a point; initialC outside the grid.
  double temperatureAtC(const glm::dvec3& pointMm) const;
  // Consumer thread: temperatures at n points (a viewer's surface vertices) into outC[0..n).
  void sampleC(const glm::vec3* pointsMm, std::size_t n, float* outC) const;
  // Consumer thread: the peak temperature and the dose a point's cell has seen.
  double peakAtC(const glm::dvec3& pointMm) const;
  double doseAtMin(const glm::dvec3& pointMm) const;
  // Consumer thread: the bone still in `bone` (fill at each cell's centre) past the damage
  // dose, mm3. damagedVolumeMm3() counts every cell, the bone the drill took away included.
  double damagedBoneVolumeMm3(const geometry::VoxelGrid& bone) const;

  // Any thread: as the last diffuse() left them.
  double tipTemperatureC() const noexcept { return tipC_.load(std::memory_order_relaxed); }
  double peakC() const noexcept { return peakC_.load(std::memory_order_relaxed); }
  double damagedVolumeMm3() const noexcept { return damagedMm3_.load(std::memory_order_relaxed); }
  double depositedJ() const noexcept { return depositedJ_.load(std::memory_order_relaxed); }
  // Consumer thread: the cells that ever left initialC (inclusive; lo > hi: none yet), and the
  // temperatures of a box of cells (x fastest) into out: what a viewer uploads.
  void touchedCells(glm::ivec3& lo, glm::ivec3& hi) const {
    lo = touchedLo_;
    hi = touchedHi_;
  }
  void copyC(const glm::ivec3& lo, const glm::ivec3& hi, float* out) const;
  // Consumer thread: heat above initialC held by the grid (J); conserved by conduction alone.
  double heatContentJ() const;

  glm::ivec3 dims() const { return dims_; }
  double cellMm() const { return cellMm_; }
  glm::dvec3 originMm() const { return originMm_; }
  const ThermalOptions& options() const { return options_; }
  // Steps merged into one because the ring was full (the consumer fell behind); their heat goes
  // out with the next deposit() that finds room.
  std::uint64_t mergedDeposits() const noexcept { return merged_.load(std::memory_order_relaxed); }
  // Bytes held by the cells' temperatures, peaks and doses (the deposit ring aside).
  std::size_t memoryBytes() const {
    return (tC_.capacity() + scratch_.capacity()) * sizeof(double) +
           (peakC_cells_.capacity() + doseMin_.capacity()) * sizeof(float);
  }

 private:
  struct Deposit;
  struct Ring;
  std::size_t index(int i, int j, int k) const {
    return std::size_t(i) +
           std::size_t(dims_.x) * (std::size_t(j) + std::size_t(dims_.y) * std::size_t(k));
  }
  void drain();
  void spread(const Deposit& d);
  void conduct(double dtS);
  void cool(double dtS);
  void dose(double dtS);
  void growActive(const glm::ivec3& lo, const glm::ivec3& hi);

  ThermalOptions options_;
  glm::ivec3 dims_{0};
  glm::dvec3 originMm_{0.0};
  double cellMm_ = 0.0;
  double cellHeatJPerK_ = 0.0;  // heat capacity of one cell
  std::vector<double> tC_, scratch_;
  std::vector<float> peakC_cells_, doseMin_;
  std::uint64_t damagedCells_ = 0;
  glm::ivec3 activeLo_{0}, activeHi_{-1};  // cells that may differ from initialC (inclusive)
  glm::ivec3 touchedLo_{std::numeric_limits<int>::max()}, touchedHi_{-1};  // every active box
  std::unique_ptr<Ring> ring_;
  // Consumer state: the latest tip and irrigation the deposits reported.
  glm::dvec3 lastTipMm_{0.0};
  double lastRadiusMm_ = 0.0;
  bool lastIrrigation_ = false;
  bool sawDeposit_ = false;
  std::atomic<double> tipC_, peakC_, damagedMm3_{0.0}, depositedJ_{0.0};
  std::atomic<std::uint64_t> merged_{0};
};

// Thermal dose (CEM43-min) of holding tempC for dtS seconds.
double cem43Minutes(double tempC, double dtS) noexcept;

}  // namespace osteon::simulation
