#include "osteon/simulation/drilling.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "osteon/core/error.h"
#include "osteon/core/option_error.h"

namespace osteon::simulation {

void validateDrillingOptions(const DrillingOptions& options) {
  if (options.levels < 0 || options.levels > geometry::kMaxRefineDepth) {
    throw OptionError("levels", std::to_string(options.levels), "must be 0, 1 or 2");
  }
  if (options.decrement < 1) {
    throw InputError("density decrement " + std::to_string(options.decrement) +
                     ": must be at least 1");
  }
}

namespace {

double finestOf(const geometry::VoxelGrid& grid, const DrillingOptions& options) {
  validateDrillingOptions(options);
  return grid.voxelSizeMm() / double(1 << options.levels);
}

geometry::RefinementOptions withDepth(geometry::RefinementOptions r, int levels) {
  r.depth = levels;
  return r;
}

}  // namespace

DrillingSimulation::DrillingSimulation(geometry::VoxelGrid& grid,
                                       geometry::DynamicProximityHierarchy& hierarchy,
                                       const geometry::FineFillSource* source, const ToolKind kind,
                                       const ToolOptions& toolOptions,
                                       const DrillingOptions& options)
    : grid_(&grid),
      levels_(options.levels),
      decrement_(options.decrement),
      finestVoxelMm_(finestOf(grid, options)),
      voxels_(std::make_unique<geometry::RefinedVoxels>(
          grid, hierarchy, source, withDepth(options.refinement, options.levels))),
      removal_(*voxels_, std::max<std::size_t>(options.refinement.capacity, 4096)),
      model_(makeTool(kind, toolOptions, finestVoxelMm_), finestVoxelMm_, grid.voxelSizeMm(),
             options.forceModel == ForceModelKind::Seed),
      refineShells_(options.refineShells && options.levels > 0),
      refineBudget_(options.refineBudgetVoxels),
      shellSkinMm_(options.shellRefineSkinVoxels * grid.voxelSizeMm()),
      shellWalkEveryS_(0.5 * options.refinement.timeoutS) {
  grid.reserveSpareBricks(options.spareBricks);
  spareMissesAtStart_ = grid.spareMisses();
  if (!(options.querySkinVoxels >= 0.0) || !std::isfinite(options.querySkinVoxels)) {
    throw InputError("query skin " + std::to_string(options.querySkinVoxels) +
                     " voxels: must be a finite number >= 0");
  }
  if (!(options.shellRefineSkinVoxels >= 0.0) || !(options.shellRefineSkinVoxels <= 4.0)) {
    throw InputError("shell refinement skin " + std::to_string(options.shellRefineSkinVoxels) +
                     " voxels: must be a number from 0 to 4");
  }
  cached_ = options.querySkinVoxels > 0.0;
  const double vs = grid.voxelSizeMm();
  const double skinMm = options.querySkinVoxels * vs;
  if (cached_) contactCaches_ = model_.makeCaches(skinMm, options.querySliceNodes, *voxels_);
  // Each cutting part: room for every voxel its cut can reach, and caches for its cut and for
  // the refinement around it.
  const Tool& tool = model_.tool();
  for (int p = 0; p < tool.partCount; ++p) {
    const ToolPart& part = tool.parts[std::size_t(p)];
    if (cached_ && refineShells_ && !part.cuts) {
      shellRefineCaches_[std::size_t(p)] = voxels_->makeNearCache(
          part.lengthMm(), voxels_->segmentRefineReachMm(part.outerRadiusMm + shellSkinMm_), skinMm,
          options.querySliceNodes);
    }
    if (!part.cuts) continue;
    const double cutReach = voxels_->cutReachMm(part.innerRadiusMm);
    removal_.reserveCutVoxels(geometry::DphNearCache::capacityFor(part.lengthMm(), cutReach, vs));
    if (!cached_) continue;
    cutCaches_[std::size_t(p)] =
        voxels_->makeNearCache(part.lengthMm(), cutReach, skinMm, options.querySliceNodes);
    if (options.levels > 0) {
      const double refineReach = voxels_->refineReachMm(0.5 * part.lengthMm() + part.outerRadiusMm);
      refineCaches_[std::size_t(p)] =
          voxels_->makeNearCache(0.0, refineReach, skinMm, options.querySliceNodes);
    }
  }
}

StepOutput DrillingSimulation::step(const StepInput& input) {
  StepOutput out;
  const Tool& tool = model_.tool();
  ++totals_.steps;
  const glm::dvec3& tip = input.pose.tipMm;
  const glm::dquat& q = input.pose.orientation;
  if (!std::isfinite(tip.x + tip.y + tip.z + q.w + q.x + q.y + q.z + input.tS)) {
    // A broken pose from a device or a path: no contact, no cut, and it is counted.
    out.contact.nonFinite = true;
    ++totals_.nonFiniteForces;
    return out;
  }
  // Around the cutting parts, everything within the margin of their outer sphere, at once: a
  // cut acts on the finest samples present.
  for (int p = 0; p < tool.partCount; ++p) {
    const ToolPart& part = tool.parts[std::size_t(p)];
    if (!part.cuts) continue;
    const glm::dvec3 a = input.pose.toWorld(part.aMm), b = input.pose.toWorld(part.bMm);
    out.refined +=
        voxels_->refineAround(0.5 * (a + b), 0.5 * part.lengthMm() + part.outerRadiusMm, input.tS,
                              cached_ ? &refineCaches_[std::size_t(p)] : nullptr);
  }
  // Around the other parts (the drill's shaft), the bone their shell reaches along their core,
  // within what is left of the step's budget; the rest in the following steps.
  if (refineShells_) {
    for (int p = 0; p < tool.partCount; ++p) {
      const ToolPart& part = tool.parts[std::size_t(p)];
      if (part.cuts) continue;
      const glm::dvec3 a = input.pose.toWorld(part.aMm), b = input.pose.toWorld(part.bMm);
      ShellWalk& last = shellWalks_[std::size_t(p)];
      // Since the last walk the core moved less than the skin: every voxel the shell can reach
      // now lay within the walk's reach then (a point's distance to a segment moves no more
      // than the segment's ends), and was refined and kept alive.
      const double moved = std::max(glm::length(a - last.aMm), glm::length(b - last.bMm));
      if (last.walked && !last.deferred && moved < shellSkinMm_ && input.tS >= last.tS &&
          input.tS - last.tS < shellWalkEveryS_) {
        continue;
      }
      const std::size_t spent = std::size_t(out.refined);
      const std::size_t budget = refineBudget_ == 0      ? std::numeric_limits<std::size_t>::max()
                                 : refineBudget_ > spent ? refineBudget_ - spent
                                                         : 0;
      int deferred = 0;
      const int created = voxels_->refineNearSegment(
          a, b, part.outerRadiusMm + shellSkinMm_, input.tS,
          cached_ ? &shellRefineCaches_[std::size_t(p)] : nullptr, budget, deferred);
      out.refined += created;
      out.deferred += deferred;
      last = ShellWalk{a, b, input.tS, true, deferred > 0};
    }
  }
  out.contact = model_.compute(*voxels_, input.pose, cached_ ? &contactCaches_ : nullptr);
  if (input.drillOn) {
    for (int p = 0; p < tool.partCount; ++p) {
      const ToolPart& part = tool.parts[std::size_t(p)];
      if (!part.cuts) continue;
      const CutVolume cut{input.pose.toWorld(part.aMm), input.pose.toWorld(part.bMm),
                          part.innerRadiusMm, part.cutsOnSideOnly};
      const RemovalResult r =
          removal_.removeIn(cut, decrement_, cached_ ? &cutCaches_[std::size_t(p)] : nullptr);
      out.removal.removedFill += r.removedFill;
      out.removal.samplesRemoved += r.samplesRemoved;
      out.removal.samplesDecremented += r.samplesDecremented;
      out.removal.voxelsEmptied += r.voxelsEmptied;
    }
  }
  voxels_->expire(input.tS);
  if (cached_) {
    std::uint64_t walks = 0, reuses = 0;
    for (std::size_t p = 0; p < std::size_t(kMaxToolParts); ++p) {
      walks += contactCaches_.shell[p].walks() + cutCaches_[p].walks() + refineCaches_[p].walks() +
               shellRefineCaches_[p].walks();
      reuses += contactCaches_.shell[p].reuses() + cutCaches_[p].reuses() +
                refineCaches_[p].reuses() + shellRefineCaches_[p].reuses();
    }
    totals_.stepsThatWalked += walks > totals_.queryWalks ? 1 : 0;
    totals_.queryWalks = walks;
    totals_.queryReuses = reuses;
  }
  if (out.deferred > 0) {
    ++totals_.stepsDeferred;
    totals_.voxelsDeferred += std::uint64_t(out.deferred);
  }
  totals_.removedFill += out.removal.removedFill;
  totals_.samplesRemoved += out.removal.samplesRemoved;
  totals_.voxelsEmptied += out.removal.voxelsEmptied;
  totals_.nonFiniteForces += out.contact.nonFinite ? 1 : 0;
  totals_.brickAllocations = grid_->spareMisses() - spareMissesAtStart_;
  totals_.cutOverflows = removal_.cutOverflows();
  totals_.refinePoolExhausted = voxels_->poolExhausted();
  totals_.maskOverflows = voxels_->maskOverflows();
  return out;
}

double DrillingSimulation::removedVolumeMm3() const {
  return double(totals_.removedFill) / double(geometry::kFillFull) * grid_->voxelVolumeMm3();
}

}  // namespace osteon::simulation
