#include "osteon/simulation/runtime.h"

#include "osteon/simulation/live.h"

#include "osteon/core/interrupt.h"

#include <atomic>
#include <chrono>
#include <cmath>
#include <sstream>
#include <thread>

namespace osteon::simulation {

RuntimeResult runThreaded(DrillingSimulation& sim, geometry::VoxelGrid& grid, PoseSource& source, ForceSink* sink,
                          const geometry::SurfaceOptions& surfaceOptions, const RuntimeOptions& options,
                          geometry::SurfaceMesh* finalSurface) {
  const auto periods = std::uint64_t(std::llround(options.durationS / options.periodS)) + 1;
  LiveRuntime live(sim, grid, source, sink, surfaceOptions, options, periods);
  live.start();
  // The visual thread: as fast as it can, the handed-over bricks into the surface. A surface
  // that failed will not be right again: the run has failed, so the loops stop now.
  std::atomic<bool> loopsOver{false}, visualFailed{false};
  std::thread visual([&] {
    while (!loopsOver.load(std::memory_order_acquire)) {
      try {
        if (live.updateSurface() == 0.0) std::this_thread::sleep_for(std::chrono::microseconds(500));
      } catch (...) {  // RuntimeFault: the error is kept in live.visualFault()
        visualFailed.store(true, std::memory_order_release);
        return;
      }
    }
  });
  // SIGINT/SIGTERM stop the loops early; the caller throws Interrupted.
  while (!live.loopsDone() && !visualFailed.load(std::memory_order_acquire) && !interrupted()) {
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  loopsOver.store(true, std::memory_order_release);
  visual.join();
  RuntimeResult result = live.stop();
  if (!result.visualFault.empty()) {
    std::ostringstream s;
    s.precision(3);
    s << std::fixed << result.visualFault << "; the haptic and collision loops were stopped cleanly after "
      << result.stats.collisionSteps << " steps (t = " << live.display().tS << " s)";
    throw RuntimeFault(s.str());
  }
  if (finalSurface) *finalSurface = live.visualSurface().mesh();
  return result;
}

}  // namespace osteon::simulation
