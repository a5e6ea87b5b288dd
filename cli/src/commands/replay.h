// `osteon replay LOG.csv MESH`: a device recording replayed through the safety layer into a
// deterministic session, written as `drill` writes its runs. With --igtl it is played at its
// own pace on the threaded runtime instead, served over OpenIGTLink while it runs.
#pragma once

#include <string>

#include "commands/drill.h"
#include "osteon/devices/recording.h"
#include "osteon/simulation/bone_source.h"
#include "support/feel_options.h"
#include "support/igtl_serve.h"

namespace osteon::cli {

struct ReplayCommandOptions {
  std::string log;              // a recording: t,x,y,z,qw,qx,qy,qz,buttons,pedal,drill_on
  simulation::BoneSource bone;  // a mesh or `default`
  int levels = 2;
  std::string tool = "drill";
  std::string outDir = ".";
  bool json = false;
  bool allowEmpty =
      false;             // a recording that never meets bone exits 0 (still "empty": true), not 1
  std::string coupling;  // proxy (the default) or direct
  IgtlCommandOptions igtl;
  FeelCommandOptions feel;
  std::string audioOut;  // render the drill's sound to this WAV (support/audio_out.h)
};

int runReplay(const ReplayCommandOptions& options);
// The same run with `extension`'s additions (deterministic replays only: the threaded one, for
// --igtl, takes none), of `recording` when it was read already (else options.log is read).
int runReplay(const ReplayCommandOptions& options, const DrillExtension& extension,
              devices::Recording* recording = nullptr);

}  // namespace osteon::cli
