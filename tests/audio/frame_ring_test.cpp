// The ring between the producer (1 kHz rows) and the audio thread: nothing dropped at 1 kHz,
// drops counted when nobody reads, and the producer's side allocates nothing.
#include "osteon/audio/frame_ring.h"

#include <atomic>
#include <chrono>
#include <thread>

#include <gtest/gtest.h>

#include "osteon/audio/player.h"
#include "support/allocation_counter.h"

namespace osteon::audio {
namespace {

TEST(FrameRing, OneKilohertzProducerDropsNothing) {
  FrameRing ring;
  std::atomic<bool> done{false};
  std::uint64_t received = 0;
  double lastT = -1.0;
  bool ordered = true;
  std::thread audio([&] {
    // As the player's thread does: look every 5 ms, take what came.
    SoundFrame f;
    while (!done.load(std::memory_order_acquire)) {
      while (ring.pop(f)) {
        ordered = ordered && f.tS > lastT;
        lastT = f.tS;
        ++received;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    while (ring.pop(f)) ++received;
  });
  const std::uint64_t before = test::threadAllocations();
  auto next = std::chrono::steady_clock::now();
  for (int i = 0; i < 1000; ++i) {  // one second of rows at 1 kHz
    ring.push({i * 1e-3, 1000.0, 1.0, 0.5, true});
    next += std::chrono::microseconds(1000);
    std::this_thread::sleep_until(next);
  }
  EXPECT_EQ(test::threadAllocations(), before);
  done.store(true, std::memory_order_release);
  audio.join();
  EXPECT_EQ(ring.frames(), 1000u);
  EXPECT_EQ(ring.dropped(), 0u);
  EXPECT_EQ(received, 1000u);
  EXPECT_TRUE(ordered);
}

TEST(FrameRing, FullRingDropsAndCounts) {
  FrameRing ring;
  for (std::size_t i = 0; i < FrameRing::kCapacity + 10; ++i) ring.push({});
  EXPECT_EQ(ring.frames(), FrameRing::kCapacity + 10);
  EXPECT_EQ(ring.dropped(), 10u);
}

TEST(SoundPlayer, PushAllocatesNothingAndNeverFails) {
  // With a device or without (this machine has none), the player starts and takes frames.
  SoundPlayer player;
  if (!player.device()) {
    EXPECT_FALSE(player.deviceError().empty());
  }
  const std::uint64_t before = test::threadAllocations();
  for (int i = 0; i < 500; ++i) player.push({i * 1e-3, 1000.0, 2.0, 1.0, true});
  player.setMuted(true);
  EXPECT_EQ(test::threadAllocations(), before);
  EXPECT_EQ(player.frames(), 500u);
  EXPECT_TRUE(player.muted());
}

}  // namespace
}  // namespace osteon::audio
