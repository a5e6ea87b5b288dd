// `osteon experiment seed`: the seed's section 4 rerun. Force logs per run, the jitter table
// (Markdown and JSON) and force plots in the manner of the seed's Figs. 6-8, drawn by gnuplot.
// `osteon experiment heat`: Augustin et al. 2008's drilling temperatures (experiment_heat.cpp).
#pragma once

#include <string>

#include "osteon/simulation/bone_source.h"

namespace osteon::cli {

struct ExperimentCommandOptions {
  std::string name;             // "seed" or "heat"
  simulation::BoneSource bone;  // the humerus, `default` by default
  std::string outDir;           // empty: experiment-NAME
  bool json = false;
};

int runExperiment(const ExperimentCommandOptions& options);
int runHeatExperiment(const ExperimentCommandOptions& options);

}  // namespace osteon::cli
