// The loader of libosteon_dicom.so (dicom_plugin_abi.h): the plugin is opened the first time a
// DICOM volume is read, so programs that read none never load GDCM.
#include <dlfcn.h>
#include <filesystem>
#include <mutex>
#include <sstream>

#include "io/dicom_child.h"
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

// The plugin names the slice at fault; for a single file that is the path itself, named once.
std::string pluginReason(const std::string& path, std::string reason) {
  std::error_code ec;
  const std::string own = std::filesystem::path(path).filename().string() + ": ";
  if (!std::filesystem::is_directory(path, ec) && reason.rfind(own, 0) == 0)
    reason = reason.substr(own.size());
  return reason;
}

// A failed call's one line: the memory check's refusal when it refused, else the plugin's reason.
void refuseFailed(const std::string& path, const DicomCallResult& r) {
  if (r.code != 0 && !r.refusal.empty()) throw InputError(r.refusal);
  if (r.code != 0) throw InputError(path + ": " + pluginReason(path, r.error));
}

}  // namespace

StoredVolume readDicom(const std::string& path, const std::string& seriesUid) {
  std::error_code ec;
  if (!std::filesystem::is_directory(path, ec)) requireInputFile(path);
  const Plugin& p = plugin();
  StoredVolume out;
  const DicomCallResult read = callDicomPlugin(
      path, true, out.volume.data,
      [&](osteon_dicom_volume* v, osteon_dicom_alloc_fn alloc, osteon_dicom_progress_fn progress,
          void* context, char* errbuf, std::size_t errlen) {
        return p.read(path.c_str(), seriesUid.c_str(), v, alloc, progress, context, errbuf, errlen);
      });
  refuseFailed(path, read);
  const osteon_dicom_volume& v = read.volume;
  RawVolume& raw = out.volume;
  for (int a = 0; a < 3; ++a) raw.sizes[a] = v.sizes[a];
  raw.type = v.type;
  raw.scalarBytes = dicomTypeBytes(raw.type);
  raw.seriesUid = v.series_uid;
  raw.seriesDescription = v.series_description;
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

using io::plugin;
using io::Plugin;

std::vector<DicomSeries> listDicomSeries(const std::string& path) {
  const Plugin& p = plugin();
  std::vector<unsigned char> text;
  const io::DicomCallResult r = io::callDicomPlugin(
      path, false, text,
      [&](osteon_dicom_volume*, osteon_dicom_alloc_fn alloc, osteon_dicom_progress_fn progress,
          void* context, char* errbuf, std::size_t errlen) {
        return p.list(path.c_str(), alloc, progress, context, errbuf, errlen);
      });
  io::refuseFailed(path, r);
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
