// The DICOM plugin's calls run in a child process (dicom_child.h): a shared page carries the
// plugin's answer and heartbeat back, a memfd the bytes it decoded.
#include "io/dicom_child.h"

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <new>
#include <sys/mman.h>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

#include "io/huge_pages.h"
#include "io/volume_place.h"
#include "osteon/core/error.h"

namespace osteon::geometry::io {

namespace {

// A step the plugin announced is allowed this much more per pixel (a multi-frame file decodes
// in one call; slices beat one by one): JPEG 2000 decodes a million pixels in about 0.1 s here.
constexpr double kSecondsPerPixel = 1e-6;

// Written by the child, read by this process once the child is gone (the heartbeat: while it runs).
struct Shared {
  std::atomic<std::uint64_t> beats{0};
  std::atomic<std::uint64_t> nextPixels{0};
  int code = 0;
  int returned = 0;         // 1: the plugin call returned (a child that threw says 0)
  std::uint64_t bytes = 0;  // what the call allocated, in the memfd
  osteon_dicom_volume volume{};
  char error[1024] = {};
  char refusal[1024] = {};
};

template <std::size_t N>
void copyField(char (&to)[N], const std::string& text) {
  const std::size_t n = std::min(text.size(), N - 1);
  std::memcpy(to, text.data(), n);
  to[n] = '\0';
}

// The volume a call described, checked against the machine's memory before it is allocated.
std::string memoryRefusal(const std::string& path, const osteon_dicom_volume& v) {
  try {
    refuseOverVolumeMemory(path, glm::ivec3(v.sizes[0], v.sizes[1], v.sizes[2]),
                           dicomTypeBytes(v.type));
  } catch (const InputError& e) {
    return e.what();
  }
  return {};
}

std::string outOfMemory(const std::string& path, std::size_t bytes) {
  return path + ": out of memory for the volume (" + std::to_string(bytes) + " bytes)";
}

// The child's side: the bytes go to the memfd, mapped shared.
struct ChildSide {
  Shared* shared;
  int fd;
  const std::string* path;
  bool volumeSized;
};

void* childAllocate(void* context, std::size_t bytes) {
  auto& c = *static_cast<ChildSide*>(context);
  const std::string refusal =
      c.volumeSized ? memoryRefusal(*c.path, c.shared->volume) : std::string();
  if (!refusal.empty()) {
    copyField(c.shared->refusal, refusal);
    return nullptr;
  }
  // Populated in one call: a page fault a 4 KiB page costs more (45,000 for a clinical CT).
  const std::size_t mapped = std::max<std::size_t>(bytes, 1);
  void* p = ftruncate(c.fd, off_t(mapped)) == 0
                ? mmap(nullptr, mapped, PROT_READ | PROT_WRITE, MAP_SHARED | MAP_POPULATE, c.fd, 0)
                : MAP_FAILED;
  if (p == MAP_FAILED) {
    copyField(c.shared->refusal, outOfMemory(*c.path, bytes));
    return nullptr;
  }
  c.shared->bytes = bytes;
  return p;
}

void childBeat(void* context, unsigned long long nextPixels) {
  Shared& s = *static_cast<ChildSide*>(context)->shared;
  s.nextPixels.store(nextPixels);
  s.beats.fetch_add(1);
}

// This process's side when no child can be started: the bytes go to `data` directly.
struct HereSide {
  const std::string* path;
  std::vector<unsigned char>* data;
  const osteon_dicom_volume* volume;  // null: no memory check (a list's text)
  std::string refusal;
};

void* hereAllocate(void* context, std::size_t bytes) {
  auto& h = *static_cast<HereSide*>(context);
  if (h.volume) h.refusal = memoryRefusal(*h.path, *h.volume);
  if (!h.refusal.empty()) return nullptr;
  try {
    h.data->resize(bytes);
    return h.data->data();
  } catch (const std::bad_alloc&) {
    h.refusal = outOfMemory(*h.path, bytes);
  }
  return nullptr;
}

DicomCallResult callHere(const std::string& path, bool volumeSized,
                         std::vector<unsigned char>& data, const DicomPluginCall& call) {
  DicomCallResult r;
  HereSide here{&path, &data, volumeSized ? &r.volume : nullptr, {}};
  char error[1024] = {};
  r.code = call(&r.volume, hereAllocate, nullptr, &here, error, sizeof error);
  r.error = error;
  r.refusal = here.refusal;
  return r;
}

std::string secondsText(double s) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", s);
  return text;
}

// Waits for the child while its heartbeat goes on; a child that stops beating is killed.
int awaitChild(pid_t child, const Shared& shared, const std::string& path, double quietSeconds) {
  using Clock = std::chrono::steady_clock;
  int status = 0;
  std::uint64_t seen = shared.beats.load();
  Clock::time_point last = Clock::now();
  for (;;) {
    const pid_t done = waitpid(child, &status, WNOHANG);
    if (done == child || (done < 0 && errno != EINTR)) return done == child ? status : 0;
    const Clock::time_point now = Clock::now();
    if (shared.beats.load() != seen) {
      seen = shared.beats.load();
      last = now;
    }
    const double allowed = quietSeconds + double(shared.nextPixels.load()) * kSecondsPerPixel;
    if (std::chrono::duration<double>(now - last).count() > allowed) {
      kill(child, SIGKILL);
      waitpid(child, &status, 0);
      throw InputError(path + ": GDCM made no progress reading it for " + secondsText(allowed) +
                       " s (a hung read)");
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
}

// The memfd's bytes into `data`, its pages freed as they are taken: the values exist once.
void takeBytes(int fd, std::uint64_t bytes, std::vector<unsigned char>& data,
               const std::string& path) {
  try {
    data.reserve(std::size_t(bytes));
    adviseHugePages(data.data(), std::size_t(bytes));
    data.resize(std::size_t(bytes));
  } catch (const std::bad_alloc&) {
    throw InputError(outOfMemory(path, std::size_t(bytes)));
  }
  constexpr std::uint64_t kChunk = std::uint64_t(16) << 20;
  for (std::uint64_t at = 0; at < bytes;) {
    const std::size_t n = std::size_t(std::min(kChunk, bytes - at));
    const ssize_t got = pread(fd, data.data() + at, n, off_t(at));
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0)
      throw std::runtime_error("cannot take the decoded DICOM values: " +
                               std::string(std::strerror(errno)));
    (void)fallocate(fd, FALLOC_FL_PUNCH_HOLE | FALLOC_FL_KEEP_SIZE, off_t(at), off_t(got));
    at += std::uint64_t(got);
  }
}

// The shared page and the memfd, released however the call ends.
struct Handoff {
  int fd = -1;
  void* page = MAP_FAILED;
  ~Handoff() {
    if (page != MAP_FAILED) munmap(page, sizeof(Shared));
    if (fd >= 0) close(fd);
  }
};

}  // namespace

std::size_t dicomTypeBytes(const std::string& type) {
  if (type == "uint8" || type == "int8") return 1;
  if (type == "uint16" || type == "int16") return 2;
  return 4;
}

DicomCallResult callDicomPlugin(const std::string& path, bool volumeSized,
                                std::vector<unsigned char>& data, const DicomPluginCall& call,
                                double quietSeconds) {
  Handoff h;
  h.fd = memfd_create("osteon-dicom", MFD_CLOEXEC);
  if (h.fd >= 0)
    h.page =
        mmap(nullptr, sizeof(Shared), PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);
  if (h.page == MAP_FAILED) return callHere(path, volumeSized, data, call);
  Shared& shared = *new (h.page) Shared;
  const pid_t child = fork();
  if (child < 0) return callHere(path, volumeSized, data, call);  // no process to spare
  if (child == 0) {
    // GDCM's assertion and warnings stay in the child: the parent says it in one line.
    const int quiet = open("/dev/null", O_WRONLY);
    if (quiet >= 0) dup2(quiet, STDERR_FILENO);
    // A crash is the child's death, not a handler's tidy exit (a fuzzer's, a sanitizer's).
    for (const int sig : {SIGABRT, SIGSEGV, SIGBUS, SIGFPE, SIGILL}) std::signal(sig, SIG_DFL);
    ChildSide side{&shared, h.fd, &path, volumeSized};
    try {
      shared.code =
          call(&shared.volume, childAllocate, childBeat, &side, shared.error, sizeof shared.error);
      shared.returned = 1;
    } catch (...) {
    }
    _exit(0);
  }
  const int status = awaitChild(child, shared, path, quietSeconds);
  // The child exits 0 whatever the plugin said; anything else is a crash a handler caught.
  if (WIFSIGNALED(status) || (WIFEXITED(status) && WEXITSTATUS(status) != 0)) {
    const std::string how = WIFSIGNALED(status) ? strsignal(WTERMSIG(status)) : "a crash";
    throw InputError(path + ": GDCM aborted reading it (" + how + "): a malformed DICOM file");
  }
  if (!shared.returned) throw InputError(path + ": GDCM failed reading it");
  DicomCallResult r;
  r.code = shared.code;
  r.error = shared.error;
  r.refusal = shared.refusal;
  r.volume = shared.volume;
  if (r.code == 0) takeBytes(h.fd, shared.bytes, data, path);
  return r;
}

}  // namespace osteon::geometry::io
