#include "osteon/audio/player.h"

#include <AL/al.h>
#include <AL/alc.h>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <dlfcn.h>
#include <thread>

#include "osteon/audio/frame_ring.h"

namespace osteon::audio {

namespace {

constexpr std::size_t kBufferSamples = 1024;  // 23 ms at 44.1 kHz
constexpr int kBuffers = 4;                   // ~93 ms queued: the latency, and the margin

extern "C" void quietAlsa(const char*, int, const char*, int, const char*, ...) {}

// Without a device, OpenAL Soft and ALSA each print lines of their own on stderr; the caller
// says it once instead. ALSOFT_LOGLEVEL set by the user is kept; ALSA's handler is set in the
// libasound OpenAL Soft loads (the same soname gives the same library).
void quietAudioLibraries() {
  setenv("ALSOFT_LOGLEVEL", "0", 0);
  if (void* alsa = dlopen("libasound.so.2", RTLD_NOW | RTLD_GLOBAL)) {
    using Handler = void (*)(const char*, int, const char*, int, const char*, ...);
    using SetHandler = int (*)(Handler);
    if (void* set = dlsym(alsa, "snd_lib_error_set_handler")) {
      reinterpret_cast<SetHandler>(set)(quietAlsa);
    }
  }
}

}  // namespace

struct SoundPlayer::Impl {
  FrameRing ring;
  std::atomic<std::uint64_t> framesWithoutDevice{0};
  std::atomic<bool> muted{false};
  std::atomic<bool> stop{false};
  std::string error;
  ALCdevice* device = nullptr;
  ALCcontext* context = nullptr;
  ALuint source = 0;
  std::array<ALuint, kBuffers> buffers{};
  DrillSound sound;
  SoundFrame latest;
  std::thread thread;

  bool open();
  void close();
  void drain();
  void fill(ALuint buffer);
  void run();
};

bool SoundPlayer::Impl::open() {
  quietAudioLibraries();
  device = alcOpenDevice(nullptr);
  if (!device) {
    error = "no audio device could be opened";
    return false;
  }
  context = alcCreateContext(device, nullptr);
  if (!context || !alcMakeContextCurrent(context)) {
    error = "the audio device gave no context";
    close();
    return false;
  }
  alGenSources(1, &source);
  alGenBuffers(kBuffers, buffers.data());
  if (alGetError() != AL_NO_ERROR) {
    error = "the audio device refused a streaming source";
    close();
    return false;
  }
  return true;
}

void SoundPlayer::Impl::close() {
  if (context) {
    if (source) {
      alSourceStop(source);
      alSourcei(source, AL_BUFFER, 0);
      alDeleteSources(1, &source);
      alDeleteBuffers(kBuffers, buffers.data());
    }
    alcMakeContextCurrent(nullptr);
    alcDestroyContext(context);
    context = nullptr;
  }
  if (device) alcCloseDevice(device);
  device = nullptr;
}

// The frames that came since the last look: the newest sets speed and load, the removal rate
// is their mean (removal comes in bursts, step by step).
void SoundPlayer::Impl::drain() {
  SoundFrame f;
  double removal = 0.0;
  int n = 0;
  while (ring.pop(f)) {
    latest = f;
    removal += f.removalMm3PerS;
    ++n;
  }
  if (n == 0) return;
  latest.removalMm3PerS = removal / n;
  sound.setTarget(latest);
}

void SoundPlayer::Impl::fill(ALuint buffer) {
  std::array<float, kBufferSamples> samples{};
  std::array<ALshort, kBufferSamples> pcm{};
  sound.setMasterGain(muted.load(std::memory_order_relaxed) ? 0.0 : 1.0);
  sound.render(samples.data(), samples.size());
  for (std::size_t i = 0; i < samples.size(); ++i) {
    pcm[i] = static_cast<ALshort>(std::lround(static_cast<double>(samples[i]) * 32767.0));
  }
  alBufferData(buffer, AL_FORMAT_MONO16, pcm.data(), static_cast<ALsizei>(sizeof(pcm)),
               static_cast<ALsizei>(kSampleRateHz));
  alSourceQueueBuffers(source, 1, &buffer);
}

void SoundPlayer::Impl::run() {
  alcMakeContextCurrent(context);
  sound.setTarget(SoundFrame{0.0, 1000.0, 0.0, 0.0, false});  // silent until the first frame
  for (ALuint b : buffers) fill(b);
  alSourcePlay(source);
  while (!stop.load(std::memory_order_acquire)) {
    drain();
    ALint processed = 0;
    alGetSourcei(source, AL_BUFFERS_PROCESSED, &processed);
    for (; processed > 0; --processed) {
      ALuint b = 0;
      alSourceUnqueueBuffers(source, 1, &b);
      fill(b);
    }
    ALint state = AL_PLAYING;
    alGetSourcei(source, AL_SOURCE_STATE, &state);
    if (state != AL_PLAYING) alSourcePlay(source);  // an underrun stopped it
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
}

SoundPlayer::SoundPlayer() : impl_(std::make_unique<Impl>()) {
  if (impl_->open()) impl_->thread = std::thread([this] { impl_->run(); });
}

SoundPlayer::~SoundPlayer() {
  impl_->stop.store(true, std::memory_order_release);
  if (impl_->thread.joinable()) impl_->thread.join();
  impl_->close();
}

bool SoundPlayer::device() const {
  return impl_->device != nullptr;
}
const std::string& SoundPlayer::deviceError() const {
  return impl_->error;
}

void SoundPlayer::push(const SoundFrame& frame) noexcept {
  if (!impl_->device) {
    impl_->framesWithoutDevice.fetch_add(1, std::memory_order_relaxed);
    return;
  }
  impl_->ring.push(frame);
}

void SoundPlayer::setMuted(bool muted) noexcept {
  impl_->muted.store(muted, std::memory_order_relaxed);
}
bool SoundPlayer::muted() const noexcept {
  return impl_->muted.load(std::memory_order_relaxed);
}
std::uint64_t SoundPlayer::frames() const noexcept {
  return impl_->ring.frames() + impl_->framesWithoutDevice.load(std::memory_order_relaxed);
}
std::uint64_t SoundPlayer::dropped() const noexcept {
  return impl_->ring.dropped();
}

}  // namespace osteon::audio
