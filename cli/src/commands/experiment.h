// `osteon experiment seed`: the seed's section 4 rerun. Force logs per run, the jitter table
// (Markdown and JSON) and force plots in the manner of the seed's Figs. 6-8, drawn by gnuplot.
#pragma once

#include <string>

#include "osteon/simulation/bone_source.h"

namespace osteon::cli {

struct ExperimentCommandOptions {
  std::string name;             // "seed"
  simulation::BoneSource bone;  // the humerus, `default` by default
  std::string outDir = "experiment-seed";
  bool json = false;
};

int runExperiment(const ExperimentCommandOptions& options);

}  // namespace osteon::cli
