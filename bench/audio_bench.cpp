// The drill's sound: the synthesiser's cost per second of audio (it must stay far below real
// time on the player's thread), and a 7 s run's rows rendered to a WAV (--audio-out's cost).
#include <cstdio>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "osteon/audio/drill_sound.h"
#include "osteon/audio/wav_writer.h"

namespace {

using osteon::audio::DrillSound;
using osteon::audio::kSampleRateHz;
using osteon::audio::SoundFrame;

void BM_DrillSoundOneSecond(benchmark::State& state) {
  DrillSound sound;
  sound.setTarget({0.0, 1000.0, 10.0, 2.0, true});
  std::vector<float> out(static_cast<std::size_t>(kSampleRateHz));
  for (auto _ : state) {
    sound.render(out.data(), out.size());
    benchmark::DoNotOptimize(out.data());
  }
}
BENCHMARK(BM_DrillSoundOneSecond)->Unit(benchmark::kMillisecond);

void BM_WavRecordingPortal5Rows(benchmark::State& state) {
  const std::string path = "/tmp/osteon_bench_audio.wav";
  for (auto _ : state) {
    osteon::audio::WavRecording wav(path);
    for (int i = 1; i <= 7000; ++i) wav.add({i * 1e-3, 1000.0, i > 900 ? 15.0 : 0.0, 2.5, true});
    wav.finish();
  }
  std::remove(path.c_str());
}
BENCHMARK(BM_WavRecordingPortal5Rows)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
