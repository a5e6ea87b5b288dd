#include "osteon/simulation/runtime.h"

#include "osteon/simulation/live.h"

#include <atomic>
#include <chrono>
#include <cmath>
#include <thread>

namespace osteon::simulation {

RuntimeResult runThreaded(DrillingSimulation& sim, geometry::VoxelGrid& grid, PoseSource& source, ForceSink* sink,
                          const geometry::SurfaceOptions& surfaceOptions, const RuntimeOptions& options,
                          geometry::SurfaceMesh* finalSurface) {
  const auto periods = std::uint64_t(std::llround(options.durationS / options.periodS)) + 1;
  LiveRuntime live(sim, grid, source, sink, surfaceOptions, options, periods);
  live.start();
  // The visual thread: as fast as it can, the handed-over bricks into the surface.
  std::atomic<bool> loopsOver{false};
  std::thread visual([&] {
    while (!loopsOver.load(std::memory_order_acquire)) {
      if (live.updateSurface() == 0.0) std::this_thread::sleep_for(std::chrono::microseconds(500));
    }
  });
  while (!live.loopsDone()) std::this_thread::sleep_for(std::chrono::milliseconds(2));
  loopsOver.store(true, std::memory_order_release);
  visual.join();
  RuntimeResult result = live.stop();
  if (finalSurface) *finalSurface = live.visualSurface().mesh();
  return result;
}

}  // namespace osteon::simulation
