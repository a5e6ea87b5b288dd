// A drilled grid's first surface, extracted on a thread of its own while steps already change
// the grid (Session's kept surface, the live runtime's visual side): it reads a copy that does
// not change (`asItWas`), and the updater then follows the grid.
#pragma once

#include <chrono>
#include <cstdint>
#include <future>
#include <memory>

#include "osteon/core/timing.h"
#include "osteon/geometry/surface/surface_updater.h"

namespace osteon::simulation {

class SurfaceBuild {
 public:
  // Both grids must outlive this object, whose destructor waits for the build.
  void start(const geometry::VoxelGrid& grid, const geometry::SurfaceOptions& options,
             const geometry::VoxelGrid& asItWas) {
    future_ = std::async(std::launch::async, [&grid, &asItWas, options] {
      const Clock::time_point begin = Clock::now();
      Built built;
      built.updater = std::make_unique<geometry::SurfaceUpdater>(grid, options, asItWas);
      built.done = Clock::now();
      built.ms = std::chrono::duration<double, std::milli>(built.done - begin).count();
      return built;
    });
  }
  // The updater, the first time it is asked for once built (wait: until it is); else null.
  // Rethrows what the build threw.
  std::unique_ptr<geometry::SurfaceUpdater> take(bool wait) {
    if (!future_.valid()) return nullptr;
    if (!wait && future_.wait_for(std::chrono::seconds(0)) != std::future_status::ready)
      return nullptr;
    Built built = future_.get();
    ms_ = built.ms;
    done_ = built.done;
    return std::move(built.updater);
  }
  // How long the build took, and when it ended (0 and the epoch until taken).
  double ms() const { return ms_; }
  Clock::time_point done() const { return done_; }

 private:
  struct Built {
    std::unique_ptr<geometry::SurfaceUpdater> updater;
    double ms = 0.0;
    Clock::time_point done;
  };
  std::future<Built> future_;
  double ms_ = 0.0;
  Clock::time_point done_{};
};

}  // namespace osteon::simulation
