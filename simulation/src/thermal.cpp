#include "osteon/simulation/thermal.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "osteon/core/error.h"
#include "osteon/core/handoff.h"
#include "osteon/core/option_error.h"

namespace osteon::simulation {

// The 1 kHz side reads these without a lock.
static_assert(std::atomic<double>::is_always_lock_free, "atomic<double> must be lock-free");
static_assert(std::atomic<std::uint64_t>::is_always_lock_free, "atomic<uint64_t> lock-free");

namespace {

constexpr double kPi = 3.14159265358979323846;

bool positive(double v) {
  return std::isfinite(v) && v > 0.0;
}

}  // namespace

double BoneThermalConstants::diffusivityMm2PerS() const {
  // k [W/(m K)] / (rho [g/cm3] c [J/(g K)]) : W/(m K) / (J/(cm3 K)) = 1e-6 m2/s ... in mm2/s:
  // (k / (rho c)) x 1e-6 m2/s = (k / (rho c)) mm2/s.
  return conductivityWPerMK / (densityGcm3 * specificHeatJPerGK);
}

double BoneThermalConstants::heatCapacityJPerMm3K() const {
  return densityGcm3 * specificHeatJPerGK * 1e-3;  // J/(cm3 K) -> J/(mm3 K)
}

double CuttingHeatModel::powerW(double removedMm3PerS, double rhoGcm3, double rpm,
                                double diameterMm, double thrustN) const noexcept {
  const double cutting =
      specificEnergyJPerMm3 * std::max(0.0, rhoGcm3) / 1.85 * std::max(0.0, removedMm3PerS);
  const double surfaceMPerS = kPi * diameterMm * 1e-3 * std::max(0.0, rpm) / 60.0;
  const double friction = frictionCoefficient * std::max(0.0, thrustN) * surfaceMPerS;
  const double p = cutting + friction;
  return std::isfinite(p) ? p : 0.0;
}

void validateThermalOptions(const ThermalOptions& o) {
  const struct {
    const char* field;
    double value;
  } checks[] = {{"thermal.cellMm", o.cellMm},
                {"thermal.maxCells", double(o.maxCells)},
                {"thermal.irrigationWPerM2K", o.irrigationWPerM2K + 1.0},
                {"thermal.irrigationReachMm", o.irrigationReachMm + 1.0},
                {"thermal.damageDoseMin", o.damageDoseMin},
                {"thermal.bone.conductivityWPerMK", o.bone.conductivityWPerMK},
                {"thermal.bone.densityGcm3", o.bone.densityGcm3},
                {"thermal.bone.specificHeatJPerGK", o.bone.specificHeatJPerGK},
                {"thermal.cutting.specificEnergyJPerMm3", o.cutting.specificEnergyJPerMm3 + 1.0},
                {"thermal.cutting.frictionCoefficient", o.cutting.frictionCoefficient + 1.0},
                {"thermal.cutting.heatFraction", o.cutting.heatFraction + 1.0}};
  for (const auto& c : checks) {
    if (!positive(c.value)) {
      throw OptionError(c.field, std::to_string(c.value), "must be a positive finite number");
    }
  }
  if (o.cutting.heatFraction > 1.0) {
    throw OptionError("thermal.cutting.heatFraction", std::to_string(o.cutting.heatFraction),
                      "must be within [0, 1]");
  }
  if (!std::isfinite(o.initialC) || !std::isfinite(o.irrigationC)) {
    throw OptionError("thermal.initialC", std::to_string(o.initialC), "must be finite");
  }
}

double cem43Minutes(double tempC, double dtS) noexcept {
  // R^(43 - T): 0.5^(43 - T) = 2^(T - 43) at or above 43 °C, 0.25^(43 - T) = 2^(2 (T - 43)) below.
  const double e = tempC >= 43.0 ? tempC - 43.0 : 2.0 * (tempC - 43.0);
  return dtS / 60.0 * std::exp2(e);
}

// One step's heat, as the ring carries it.
struct ThermalModel::Deposit {
  glm::dvec3 tipMm;
  double energyJ;
  double radiusMm;
  bool irrigation;
};

// 1024 steps: a second at 1 kHz before steps merge. `pending` is the producer's own.
struct ThermalModel::Ring {
  core::SpscRing<Deposit, 1024> ring;
  Deposit pending{};
  bool hasPending = false;
};

ThermalModel::ThermalModel(const geometry::VoxelGrid& grid, const ThermalOptions& options)
    : ThermalModel(grid.originMm(), grid.worldFromGrid(glm::dvec3(grid.dims())), options) {}

ThermalModel::ThermalModel(const glm::dvec3& loMm, const glm::dvec3& hiMm,
                           const ThermalOptions& options)
    : options_(options), tipC_(options.initialC), peakC_(options.initialC) {
  validateThermalOptions(options);
  const glm::dvec3 size = hiMm - loMm + 2.0 * options.marginMm;
  if (!(size.x > 0.0 && size.y > 0.0 && size.z > 0.0) || !std::isfinite(size.x + size.y + size.z))
    throw InputError("thermal grid: the box is empty or not finite");
  // Cells of cellMm, or as large as keeps the box within maxCells.
  cellMm_ = std::max(options.cellMm,
                     std::cbrt(size.x * size.y * size.z / double(options.maxCells)) * 1.0001);
  dims_ = glm::max(glm::ivec3(glm::ceil(size / cellMm_)), glm::ivec3(1));
  while (std::size_t(dims_.x) * std::size_t(dims_.y) * std::size_t(dims_.z) > options.maxCells) {
    cellMm_ *= 1.01;
    dims_ = glm::max(glm::ivec3(glm::ceil(size / cellMm_)), glm::ivec3(1));
  }
  originMm_ = loMm - options.marginMm;
  cellHeatJPerK_ = options.bone.heatCapacityJPerMm3K() * cellMm_ * cellMm_ * cellMm_;
  const std::size_t n = std::size_t(dims_.x) * std::size_t(dims_.y) * std::size_t(dims_.z);
  tC_.assign(n, options.initialC);
  scratch_.assign(n, options.initialC);
  peakC_cells_.assign(n, float(options.initialC));
  doseMin_.assign(n, 0.0f);
  ring_ = std::make_unique<Ring>();
}

ThermalModel::~ThermalModel() = default;

void ThermalModel::deposit(const HeatInput& in) noexcept {
  const double dt = std::isfinite(in.dtS) && in.dtS > 0.0 ? in.dtS : 0.0;
  double powerW = 0.0;
  if (dt > 0.0) {
    const double removalMm3PerS = std::max(0.0, in.removedMm3) / dt;
    // Friction heats only while the drill turns in bone; removal implies it.
    const double thrust = in.cutting || in.removedMm3 > 0.0 ? in.thrustN : 0.0;
    powerW = options_.cutting.powerW(removalMm3PerS, in.rhoGcm3, in.rpm, in.diameterMm, thrust);
  }
  Deposit d{in.tipMm, options_.cutting.heatFraction * powerW * dt,
            0.5 * std::max(0.0, in.diameterMm), in.irrigation};
  if (!std::isfinite(d.tipMm.x + d.tipMm.y + d.tipMm.z)) return;  // a non-finite pose: no heat
  Ring& r = *ring_;
  // While the ring is full, steps merge into one pending deposit at the latest tip.
  if (r.hasPending) {
    d.energyJ += r.pending.energyJ;
    r.hasPending = false;
  }
  if (!r.ring.push(d)) {
    r.pending = d;
    r.hasPending = true;
    merged_.fetch_add(1, std::memory_order_relaxed);
  }
}

void ThermalModel::growActive(const glm::ivec3& lo, const glm::ivec3& hi) {
  const glm::ivec3 l = glm::max(lo, glm::ivec3(0));
  const glm::ivec3 h = glm::min(hi, dims_ - 1);
  touchedLo_ = glm::min(touchedLo_, l);
  touchedHi_ = glm::max(touchedHi_, h);
  if (activeHi_.x < activeLo_.x) {
    activeLo_ = l;
    activeHi_ = h;
  } else {
    activeLo_ = glm::min(activeLo_, l);
    activeHi_ = glm::max(activeHi_, h);
  }
}

// A deposit's heat, spread evenly over the cells whose centres lie in the drill tip's sphere
// (at least the tip's own cell): the heat enters the bone at the cutting face.
void ThermalModel::spread(const Deposit& d) {
  const glm::dvec3 g = (d.tipMm - originMm_) / cellMm_;
  const double r = d.radiusMm / cellMm_;
  const glm::ivec3 lo = glm::ivec3(glm::floor(g - r)), hi = glm::ivec3(glm::floor(g + r));
  const glm::ivec3 l = glm::max(lo, glm::ivec3(0)), h = glm::min(hi, dims_ - 1);
  if (l.x > h.x || l.y > h.y || l.z > h.z) return;  // outside the grid: lost to the body
  std::size_t count = 0;
  for (int pass = 0; pass < 2; ++pass) {
    const double dT = pass == 0 ? 0.0 : d.energyJ / (cellHeatJPerK_ * double(count));
    for (int k = l.z; k <= h.z; ++k)
      for (int j = l.y; j <= h.y; ++j)
        for (int i = l.x; i <= h.x; ++i) {
          const glm::dvec3 c = glm::dvec3(i, j, k) + 0.5 - g;
          if (glm::dot(c, c) > r * r) continue;
          if (pass == 0) {
            ++count;
          } else {
            tC_[index(i, j, k)] += dT;
          }
        }
    if (pass == 0 && count == 0) {
      const glm::ivec3 c = glm::clamp(glm::ivec3(glm::floor(g)), glm::ivec3(0), dims_ - 1);
      tC_[index(c.x, c.y, c.z)] += d.energyJ / cellHeatJPerK_;
      break;
    }
  }
  growActive(lo, hi);
}

void ThermalModel::drain() {
  Deposit d{};
  double energy = 0.0;
  while (ring_->ring.pop(d)) {
    spread(d);
    energy += d.energyJ;
    lastTipMm_ = d.tipMm;
    lastRadiusMm_ = d.radiusMm;
    lastIrrigation_ = d.irrigation;
    sawDeposit_ = true;
  }
  depositedJ_.store(depositedJ_.load(std::memory_order_relaxed) + energy,
                    std::memory_order_relaxed);
}

// One explicit step of dT/dt = alpha lap T over the active box grown by a cell; the cells
// outside the grid are held at initialC (Dirichlet faces). The box then shrinks to the cells
// more than kActiveK from initialC: the heat of one drill site costs its neighbourhood only.
void ThermalModel::conduct(double dtS) {
  if (activeHi_.x < activeLo_.x) return;
  constexpr double kActiveK = 1e-6;
  growActive(activeLo_ - 1, activeHi_ + 1);
  const double f = options_.bone.diffusivityMm2PerS() * dtS / (cellMm_ * cellMm_);
  const double outside = options_.initialC;
  const std::size_t sy = std::size_t(dims_.x), sz = sy * std::size_t(dims_.y);
  glm::ivec3 lo = dims_, hi(-1);
  for (int k = activeLo_.z; k <= activeHi_.z; ++k)
    for (int j = activeLo_.y; j <= activeHi_.y; ++j)
      for (int i = activeLo_.x; i <= activeHi_.x; ++i) {
        const std::size_t c = index(i, j, k);
        const double t = tC_[c];
        const double sum =
            (i > 0 ? tC_[c - 1] : outside) + (i + 1 < dims_.x ? tC_[c + 1] : outside) +
            (j > 0 ? tC_[c - sy] : outside) + (j + 1 < dims_.y ? tC_[c + sy] : outside) +
            (k > 0 ? tC_[c - sz] : outside) + (k + 1 < dims_.z ? tC_[c + sz] : outside);
        const double next = t + f * (sum - 6.0 * t);
        scratch_[c] = next;
        if (std::abs(next - outside) > kActiveK) {
          lo = glm::min(lo, glm::ivec3(i, j, k));
          hi = glm::max(hi, glm::ivec3(i, j, k));
        }
      }
  for (int k = activeLo_.z; k <= activeHi_.z; ++k)
    for (int j = activeLo_.y; j <= activeHi_.y; ++j) {
      const std::size_t row = index(activeLo_.x, j, k);
      std::copy(scratch_.begin() + std::ptrdiff_t(row),
                scratch_.begin() + std::ptrdiff_t(row) + (activeHi_.x - activeLo_.x + 1),
                tC_.begin() + std::ptrdiff_t(row));
    }
  activeLo_ = lo;
  activeHi_ = hi;
}

// Irrigation: h (T - T_water) through one cell face per cell, exact for the step (exponential
// decay towards the water's temperature), in the sphere the water reaches around the tip.
void ThermalModel::cool(double dtS) {
  if (!lastIrrigation_ || !sawDeposit_ || options_.irrigationWPerM2K <= 0.0) return;
  const double ratePerS = options_.irrigationWPerM2K * 1e-6 /
                          (options_.bone.heatCapacityJPerMm3K() * cellMm_);  // h/(rho c L)
  const double keep = std::exp(-ratePerS * dtS);
  const glm::dvec3 g = (lastTipMm_ - originMm_) / cellMm_;
  const double r = (lastRadiusMm_ + options_.irrigationReachMm) / cellMm_;
  const glm::ivec3 lo = glm::max(glm::ivec3(glm::floor(g - r)), glm::ivec3(0));
  const glm::ivec3 hi = glm::min(glm::ivec3(glm::floor(g + r)), dims_ - 1);
  if (lo.x > hi.x || lo.y > hi.y || lo.z > hi.z) return;
  for (int k = lo.z; k <= hi.z; ++k)
    for (int j = lo.y; j <= hi.y; ++j)
      for (int i = lo.x; i <= hi.x; ++i) {
        const glm::dvec3 c = glm::dvec3(i, j, k) + 0.5 - g;
        if (glm::dot(c, c) > r * r) continue;
        double& t = tC_[index(i, j, k)];
        t = options_.irrigationC + (t - options_.irrigationC) * keep;
      }
  growActive(lo, hi);
}

// CEM43 and the peak per cell over the active box; the damaged count grows as cells cross.
void ThermalModel::dose(double dtS) {
  // Cells at initialC dose nothing below 39 °C; a grid held warmer doses everywhere.
  const bool everywhere = options_.initialC >= 39.0;
  const glm::ivec3 lo = everywhere ? glm::ivec3(0) : activeLo_;
  const glm::ivec3 hi = everywhere ? dims_ - 1 : activeHi_;
  if (hi.x < lo.x) return;
  double peak = peakC_.load(std::memory_order_relaxed);
  // At the dose, to float's accumulated rounding: 47 °C held 1 min is damage.
  const auto threshold = float(options_.damageDoseMin * (1.0 - 1e-4));
  for (int k = lo.z; k <= hi.z; ++k)
    for (int j = lo.y; j <= hi.y; ++j)
      for (int i = lo.x; i <= hi.x; ++i) {
        const std::size_t c = index(i, j, k);
        const double t = tC_[c];
        if (t > double(peakC_cells_[c])) peakC_cells_[c] = float(t);
        peak = std::max(peak, t);
        if (t < 39.0) continue;  // below 39 °C a minute adds under 0.004 CEM43-min
        const float before = doseMin_[c];
        doseMin_[c] = float(double(before) + cem43Minutes(t, dtS));
        if (before < threshold && doseMin_[c] >= threshold) ++damagedCells_;
      }
  peakC_.store(peak, std::memory_order_relaxed);
  damagedMm3_.store(double(damagedCells_) * cellMm_ * cellMm_ * cellMm_, std::memory_order_relaxed);
}

void ThermalModel::diffuse(double dtS) {
  drain();
  if (std::isfinite(dtS) && dtS > 0.0) {
    // Explicit conduction is stable for alpha dt / h^2 <= 1/6: sub-steps at 0.9 of that.
    const double limitS = 0.9 * cellMm_ * cellMm_ / (6.0 * options_.bone.diffusivityMm2PerS());
    const int n = std::max(1, int(std::ceil(dtS / limitS)));
    const double h = dtS / double(n);
    for (int s = 0; s < n; ++s) {
      conduct(h);
      cool(h);
      dose(h);
    }
  } else {
    dose(0.0);  // the peak of what was just deposited
  }
  if (sawDeposit_) tipC_.store(temperatureAtC(lastTipMm_), std::memory_order_relaxed);
}

void ThermalModel::copyC(const glm::ivec3& lo, const glm::ivec3& hi, float* out) const {
  for (int k = lo.z; k <= hi.z; ++k)
    for (int j = lo.y; j <= hi.y; ++j)
      for (int i = lo.x; i <= hi.x; ++i) *out++ = float(tC_[index(i, j, k)]);
}

double ThermalModel::temperatureAtC(const glm::dvec3& pointMm) const {
  // Trilinear over cell centres; cells beyond the grid read initialC (the held faces).
  const glm::dvec3 g = (pointMm - originMm_) / cellMm_ - 0.5;
  if (!std::isfinite(g.x + g.y + g.z)) return options_.initialC;
  const glm::dvec3 f = glm::floor(g);
  const glm::dvec3 w = g - f;
  if (glm::any(glm::lessThan(f, glm::dvec3(-1.0))) ||
      glm::any(glm::greaterThan(f, glm::dvec3(dims_))))
    return options_.initialC;
  const glm::ivec3 b(f);
  double sum = 0.0;
  for (int c = 0; c < 8; ++c) {
    const glm::ivec3 o(c & 1, (c >> 1) & 1, (c >> 2) & 1);
    const glm::ivec3 q = b + o;
    const double t =
        glm::all(glm::greaterThanEqual(q, glm::ivec3(0))) && glm::all(glm::lessThan(q, dims_))
            ? tC_[index(q.x, q.y, q.z)]
            : options_.initialC;
    const double wx = o.x ? w.x : 1.0 - w.x, wy = o.y ? w.y : 1.0 - w.y, wz = o.z ? w.z : 1.0 - w.z;
    sum += wx * wy * wz * t;
  }
  return sum;
}

void ThermalModel::sampleC(const glm::vec3* pointsMm, std::size_t n, float* outC) const {
  for (std::size_t i = 0; i < n; ++i) outC[i] = float(temperatureAtC(glm::dvec3(pointsMm[i])));
}

double ThermalModel::peakAtC(const glm::dvec3& pointMm) const {
  const glm::ivec3 c = glm::ivec3(glm::floor((pointMm - originMm_) / cellMm_));
  if (glm::any(glm::lessThan(c, glm::ivec3(0))) || glm::any(glm::greaterThanEqual(c, dims_)))
    return options_.initialC;
  return double(peakC_cells_[index(c.x, c.y, c.z)]);
}

double ThermalModel::doseAtMin(const glm::dvec3& pointMm) const {
  const glm::ivec3 c = glm::ivec3(glm::floor((pointMm - originMm_) / cellMm_));
  if (glm::any(glm::lessThan(c, glm::ivec3(0))) || glm::any(glm::greaterThanEqual(c, dims_)))
    return 0.0;
  return double(doseMin_[index(c.x, c.y, c.z)]);
}

double ThermalModel::damagedBoneVolumeMm3(const geometry::VoxelGrid& bone) const {
  if (damagedCells_ == 0) return 0.0;
  const auto threshold = float(options_.damageDoseMin * (1.0 - 1e-4));
  const bool everywhere = options_.initialC >= 39.0;  // as dose() does
  const glm::ivec3 lo = everywhere ? glm::ivec3(0) : touchedLo_;
  const glm::ivec3 hi = everywhere ? dims_ - 1 : touchedHi_;
  double fill = 0.0;
  for (int k = lo.z; k <= hi.z; ++k)
    for (int j = lo.y; j <= hi.y; ++j)
      for (int i = lo.x; i <= hi.x; ++i) {
        if (doseMin_[index(i, j, k)] < threshold) continue;
        const glm::dvec3 centreMm = originMm_ + (glm::dvec3(i, j, k) + 0.5) * cellMm_;
        const glm::ivec3 v = glm::ivec3(glm::floor(bone.gridFromWorld(centreMm)));
        fill += double(bone.fill(v)) / double(geometry::kFillFull);
      }
  return fill * cellMm_ * cellMm_ * cellMm_;
}

double ThermalModel::heatContentJ() const {
  double sum = 0.0;
  for (const double t : tC_) sum += t - options_.initialC;
  return sum * cellHeatJPerK_;
}

}  // namespace osteon::simulation
