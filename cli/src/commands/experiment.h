// `osteon experiment seed`: the seed's section 4 rerun. Force logs per run, the jitter table
// (Markdown and JSON) and force plots in the manner of the seed's Figs. 6-8, drawn by gnuplot.
// `osteon experiment heat`: Augustin et al. 2008's drilling temperatures (experiment_heat.cpp).
#pragma once

#include <string>

#include "osteon/simulation/bone_source.h"

namespace osteon::cli {

struct ExperimentCommandOptions {
  std::string name;             // "seed", "thrust" or "heat"
  simulation::BoneSource bone;  // the humerus, `default` by default
  std::string outDir;           // empty: experiment-NAME
  bool json = false;
};

int runExperiment(const ExperimentCommandOptions& options);
// `experiment thrust` (experiment_thrust.cpp): the calibrated thrust against published data.
int runThrustExperiment(const ExperimentCommandOptions& options, const std::string& outDir);
// `experiment heat` (experiment_heat.cpp): bone temperature against Augustin 2008.
int runHeatExperiment(const ExperimentCommandOptions& options);

}  // namespace osteon::cli
