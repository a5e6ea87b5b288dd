// A call into the DICOM plugin run in a child process (dicom_volume.cpp's reads and lists).
// GDCM, as Debian builds it, keeps its assertions: some malformed files abort the process from
// inside it, past any check osteon can make first. The child takes that crash; what it read
// (the plugin's answer, and the bytes it asked for: the values, or the list's text) is handed to
// this process through shared memory, so nothing is decoded twice.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "io/dicom_plugin_abi.h"

namespace osteon::geometry::io {

// One plugin call, given where its answer goes and the allocator and heartbeat to use.
using DicomPluginCall = std::function<int(osteon_dicom_volume* out, osteon_dicom_alloc_fn alloc,
                                          osteon_dicom_progress_fn progress, void* context,
                                          char* errbuf, std::size_t errlen)>;

struct DicomCallResult {
  int code = 0;         // the plugin's: 0, 2 (bad input), 3 (the buffer refused)
  std::string error;    // its reason (option references still marked)
  std::string refusal;  // the memory check's message when it refused the buffer
  osteon_dicom_volume volume{};
};

// Runs `call` in a child process; the bytes it allocates end up in `data`, checked first against
// the machine's memory when `volumeSized` (the size of the volume the call describes in `out`).
// A child that dies by a signal is refused in one line (InputError "<path>: GDCM aborted ..."),
// as is one whose heartbeat stops: no progress for quietSeconds, plus a second for every million
// pixels of a step the plugin announced. Without a process to spare the call runs in this one.
DicomCallResult callDicomPlugin(const std::string& path, bool volumeSized,
                                std::vector<unsigned char>& data, const DicomPluginCall& call,
                                double quietSeconds = 30.0);

// Bytes of one value of a type the plugin names ("uint8" ... "float").
std::size_t dicomTypeBytes(const std::string& type);

}  // namespace osteon::geometry::io
