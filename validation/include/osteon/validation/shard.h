// Splitting the nightly run into disjoint, deterministic shards (`osteon validate --shard K/N`)
// balanced by estimated cost, so N machines finish at about the same time.
//
// The unit of sharding is a case group: one model at one voxel size. Its four cases (two
// surface methods x two force modes) share one voxelization, head fit and extraction per
// method inside runValidation, so splitting a group would repeat that work on two machines;
// a nightly of 50 bones x 4 sizes still has 200 groups to balance.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "osteon/validation/validate.h"

namespace osteon::validation {

struct CaseGroup {
  std::size_t model = 0;  // index into the run's models
  double voxelSizeMm = 0.0;
  double estimatedVoxels = 0.0;  // voxels inside the model at this size, estimated cheaply
  double cost = 0.0;             // estimatedVoxels x the group's case weights
};

// Every case of a group: crack-free and naive, static and dynamic, in runValidation's order.
inline constexpr int kCasesPerGroup = 4;

// The groups of a run in runValidation's order (models, then each model's voxel sizes).
std::vector<CaseGroup> caseGroups(const std::vector<ValidationModel>& models,
                                  const ValidationOptions& options);

// The case keys ("model|voxel mm|method|mode") of the groups, in run order: what a shard
// report names its cases by, and what a merge orders them by.
std::vector<std::string> caseKeys(const std::vector<ValidationModel>& models,
                                  const std::vector<CaseGroup>& groups);
std::string caseKey(const std::string& model, double voxelSizeMm, const std::string& method,
                    const std::string& mode);

// Shard (0..shardCount-1) of each cost: longest processing time first (costs descending, ties
// by index), each to the shard with the least total so far (ties to the lowest shard). The
// same costs always give the same assignment. Throws std::invalid_argument for shardCount 0.
std::vector<std::size_t> assignShards(const std::vector<double>& costs, std::size_t shardCount);

}  // namespace osteon::validation
