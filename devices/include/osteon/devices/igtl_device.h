// `igtl:HOST:PORT[/NAME]`: a tracked tool over OpenIGTLink (a tracker through the PLUS toolkit,
// 3D Slicer, or another osteon serving --igtl). Its TRANSFORM messages named NAME, or the
// element NAME of its TDATA and QTDATA messages (any without a NAME), are the tool pose, taken from
// RAS to osteon's LPS (x and y negated, the tool frame alike: osteon's own DrillToRAS comes back as
// the pose it was sent from), in the session's frame. The drill runs while the stream does. The
// pose holds between messages (fresh at each poll, as trackers send at 20-60 Hz) until the stream
// has been silent for 250 ms: then the last sample ages, which the safety layer faults (a gap) and
// the session holds the tool. A reader thread of its own takes the stream through IgtlStreamReader
// (igtl_reader.h); poll() only reads a triple buffer.
#pragma once

#include <memory>
#include <string>

#include "osteon/devices/device.h"

namespace osteon::devices {

// argument: HOST:PORT[/NAME]. Throws InputError naming `text` when it is malformed or nothing
// listens there.
std::unique_ptr<Device> openIgtlDevice(const std::string& text, const std::string& argument);

}  // namespace osteon::devices
