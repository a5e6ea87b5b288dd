// The loader of libosteon_dicom.so (dicom_plugin_abi.h): the plugin is opened the first time a
// DICOM volume is read, so programs that read none never load GDCM.
#include <array>
#include <chrono>
#include <csignal>
#include <cstring>
#include <dlfcn.h>
#include <fcntl.h>
#include <filesystem>
#include <mutex>
#include <sstream>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

#include "io/dicom_plugin_abi.h"
#include "io/volume_place.h"
#include "io/volume_readers.h"
#include "osteon/core/error.h"
#include "osteon/core/input_file.h"
#include "osteon/core/plugin_loader.h"
#include "osteon/geometry/io/dicom_series.h"

namespace osteon::geometry::io {

namespace {

struct Plugin {
  bool loaded = false;
  osteon_dicom_read_fn read = nullptr;
  osteon_dicom_list_fn list = nullptr;
};

std::mutex gMutex;
Plugin gPlugin;

const Plugin& plugin() {
  const std::lock_guard<std::mutex> lock(gMutex);
  if (gPlugin.loaded) return gPlugin;
  const PluginPlaces places{"OSTEON_DICOM_PLUGIN", OSTEON_DICOM_PLUGIN_NAME, OSTEON_DICOM_BUILD_DIR,
                            OSTEON_DICOM_INSTALL_RELATIVE_LIBDIR, OSTEON_DICOM_INSTALL_LIBDIR};
  loadPlugin(places, "osteon's DICOM plugin (GDCM), needed to read DICOM",
             [](void* handle, const std::string& path, std::string& error) {
               const auto abi =
                   reinterpret_cast<osteon_dicom_abi_fn>(::dlsym(handle, "osteon_dicom_abi"));
               const auto read =
                   reinterpret_cast<osteon_dicom_read_fn>(::dlsym(handle, "osteon_dicom_read"));
               const auto list =
                   reinterpret_cast<osteon_dicom_list_fn>(::dlsym(handle, "osteon_dicom_list"));
               if (!abi || !read || !list) {
                 error = path + ": not an osteon DICOM plugin (missing symbols)";
                 return false;
               }
               if (abi() != OSTEON_DICOM_ABI) {
                 error = path + ": built for DICOM interface " + std::to_string(abi()) +
                         ", this osteon needs " + std::to_string(OSTEON_DICOM_ABI);
                 return false;
               }
               gPlugin = {true, read, list};
               return true;
             });
  return gPlugin;
}

std::size_t typeBytes(const std::string& type) {
  if (type == "uint8" || type == "int8") return 1;
  if (type == "uint16" || type == "int16") return 2;
  return 4;
}

// Where the plugin puts the values: the volume's own buffer, after the memory check.
struct Destination {
  const std::string* path;
  std::vector<unsigned char>* data;
  const osteon_dicom_volume* volume;  // its sizes and type are set before it asks for values
  std::string refusal;                // the memory check's message, when it refused
};

void* allocate(void* context, std::size_t bytes) {
  auto& to = *static_cast<Destination*>(context);
  try {
    if (to.volume) {
      const glm::ivec3 sizes(to.volume->sizes[0], to.volume->sizes[1], to.volume->sizes[2]);
      refuseOverVolumeMemory(*to.path, sizes, typeBytes(to.volume->type));
    }
    to.data->resize(bytes);
    return to.data->data();
  } catch (const InputError& e) {
    to.refusal = e.what();
  } catch (const std::bad_alloc&) {
    to.refusal = *to.path + ": out of memory for the volume (" + std::to_string(bytes) + " bytes)";
  }
  return nullptr;
}

// The plugin names the slice at fault; for a single file that is the path itself, named once.
std::string pluginReason(const std::string& path, std::string reason) {
  std::error_code ec;
  const std::string own = std::filesystem::path(path).filename().string() + ": ";
  if (!std::filesystem::is_directory(path, ec) && reason.rfind(own, 0) == 0)
    reason = reason.substr(own.size());
  return reason;
}

// GDCM, as Debian builds it, keeps its assertions: some malformed files abort the process from
// inside it, past any check osteon can make first. So a read runs first in a child process;
// a child that dies by a signal (or hangs past a minute) gets the file refused, and only a file
// the child read through is read again in this process.
template <typename Read>
void refuseWhatAbortsGdcm(const std::string& path, Read&& read) {
  const pid_t child = fork();
  if (child < 0) return;  // no process to spare: read in this one, as before
  if (child == 0) {
    // GDCM's assertion and warnings stay in the child: the parent says it in one line.
    const int quiet = open("/dev/null", O_WRONLY);
    if (quiet >= 0) dup2(quiet, STDERR_FILENO);
    // A crash is the child's death, not a handler's tidy exit (a fuzzer's, a sanitizer's).
    for (const int sig : {SIGABRT, SIGSEGV, SIGBUS, SIGFPE, SIGILL}) std::signal(sig, SIG_DFL);
    try {
      read();
    } catch (...) {
    }
    _exit(0);
  }
  int status = 0;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (waitpid(child, &status, WNOHANG) == 0) {
    if (std::chrono::steady_clock::now() > deadline) {
      kill(child, SIGKILL);
      waitpid(child, &status, 0);
      throw InputError(path + ": GDCM did not finish reading it within a minute");
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  // The child exits 0 whatever the plugin said; anything else is a crash a handler caught.
  if (WIFSIGNALED(status) || (WIFEXITED(status) && WEXITSTATUS(status) != 0)) {
    const std::string how = WIFSIGNALED(status) ? strsignal(WTERMSIG(status)) : "a crash";
    throw InputError(path + ": GDCM aborted reading it (" + how + "): a malformed DICOM file");
  }
}

}  // namespace

StoredVolume readDicom(const std::string& path, const std::string& seriesUid) {
  std::error_code ec;
  if (!std::filesystem::is_directory(path, ec)) requireInputFile(path);
  const Plugin& p = plugin();
  StoredVolume out;
  osteon_dicom_volume v{};
  std::array<char, 1024> error{};
  Destination to{&path, &out.volume.data, &v, {}};
  refuseWhatAbortsGdcm(path, [&] {
    p.read(path.c_str(), seriesUid.c_str(), &v, allocate, &to, error.data(), error.size());
  });
  const int code =
      p.read(path.c_str(), seriesUid.c_str(), &v, allocate, &to, error.data(), error.size());
  if (code == 3 && !to.refusal.empty()) throw InputError(to.refusal);
  if (code != 0) throw InputError(path + ": " + pluginReason(path, error.data()));
  RawVolume& raw = out.volume;
  for (int a = 0; a < 3; ++a) raw.sizes[a] = v.sizes[a];
  raw.type = v.type;
  raw.scalarBytes = typeBytes(raw.type);
  const bool scaled = v.slope != 1.0 || v.intercept != 0.0;
  raw.integer = raw.type != "float" && !scaled;
  raw.isSigned = raw.type[0] == 'i' || raw.type == "float" || v.slope < 0 || v.intercept < 0;
  if (scaled) {
    raw.slope = v.slope;
    raw.intercept = v.intercept;
  }
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) out.m[r][c] = v.m[r][c];
    out.centre0[r] = v.centre0[r];
  }
  return out;
}

}  // namespace osteon::geometry::io

namespace osteon::geometry {

using io::allocate;
using io::Destination;
using io::plugin;
using io::Plugin;
using io::pluginReason;

std::vector<DicomSeries> listDicomSeries(const std::string& path) {
  const Plugin& p = plugin();
  std::vector<unsigned char> text;
  Destination to{&path, &text, nullptr, {}};
  std::array<char, 1024> error{};
  io::refuseWhatAbortsGdcm(
      path, [&] { p.list(path.c_str(), allocate, &to, error.data(), error.size()); });
  if (p.list(path.c_str(), allocate, &to, error.data(), error.size()) != 0)
    throw InputError(to.refusal.empty() ? path + ": " + pluginReason(path, error.data())
                                        : to.refusal);
  std::vector<DicomSeries> all;
  std::istringstream lines(reinterpret_cast<const char*>(text.data()));
  std::string line;
  while (std::getline(lines, line)) {
    DicomSeries s;
    std::istringstream fields(line);
    std::string count;
    std::getline(fields, s.uid, '\t');
    std::getline(fields, count, '\t');
    std::getline(fields, s.description);
    s.slices = std::stoi(count);
    all.push_back(s);
  }
  return all;
}

int defaultDicomSeries(const std::vector<DicomSeries>& all) {
  int best = -1;
  bool tie = false;
  for (std::size_t i = 0; i < all.size(); ++i) {
    if (best < 0 || all[i].slices > all[std::size_t(best)].slices) {
      best = int(i);
      tie = false;
    } else if (all[i].slices == all[std::size_t(best)].slices) {
      tie = true;
    }
  }
  return tie ? -1 : best;
}

}  // namespace osteon::geometry
