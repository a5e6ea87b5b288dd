// `osteon validate`: the nightly run: every guarantee on models x voxel sizes x methods x modes,
// and its report (report.json with a stable schema, report.html, validate.log, crack images);
// or a shard of the run (--shard K/N), or the merge of shards (--merge, validate_merge.cpp).
#pragma once

#include <string>
#include <vector>

#include "osteon/simulation/bone_source.h"

namespace osteon::cli {

struct ValidateCommandOptions {
  std::string models = "default";  // comma-separated: default or mesh paths
  simulation::BoneSource
      source;  // each model's units or scale and volume options (input: each of models)
  std::string voxelSizes = "1.2,0.9,0.72,0.54";
  bool voxelSizesGiven = false;  // --voxel-sizes on the command line (overrides --quick's)
  bool quick = false;
  std::string outDir = "validation-report";
  std::string compare;             // a previous report.json
  std::string shard;               // "K/N": run the K-th (0-based) of N shards; empty: all
  std::vector<std::string> merge;  // shard out-dirs to merge into --out-dir instead of a run
  std::vector<std::string>
      runOptionsGiven;  // options of a run given on the command line (--models ...)
};

int runValidate(const ValidateCommandOptions& options);

}  // namespace osteon::cli
