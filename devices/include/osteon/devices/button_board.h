// `serial:PORT[@BAUD]`: the trainer's button board (an Arduino with buttons, a foot pedal and
// a knob) on a serial port, 9600 baud by default. Wire protocol, one line per state, ASCII,
// newline-terminated (a CR before the newline is ignored):
//   B=<button mask, hex>,P=<pedal 0-1023>[,K=<knob counts, signed decimal>]
// for example `B=5,P=512` or `B=1,P=0,K=-3`. B and P are required; K is the knob's counts since
// the previous line; keys osteon does not know are ignored (a later board may send more).
// A line that breaks the rules is malformed: it is counted and skipped, with its reason.
// Lines are bounded (kMaxBoardLineBytes): a longer line is dropped as it streams in, without
// memory growing, and counted malformed at its newline. A board silent for 500 ms is reported
// disconnected, and connected again when bytes come back; a port that hangs up (unplugged) is
// opened again by name until it returns.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <thread>

#include "osteon/core/handoff.h"
#include "osteon/devices/device.h"
#include "osteon/devices/serial_port.h"

namespace osteon::devices {

inline constexpr std::size_t kMaxBoardLineBytes = 256;
inline constexpr int kBoardPedalMax = 1023;

struct BoardEvent {
  enum class Kind : std::uint8_t { Line, Malformed, Disconnected, Connected };
  Kind kind = Kind::Line;
  double tS = 0.0;            // when it happened (seconds since the device opened)
  std::uint32_t buttons = 0;  // Line: B
  int pedal = 0;              // Line: P, 0..1023
  std::int64_t knob = 0;      // Line: K (0 when absent)
  bool hasKnob = false;
  const char* reason = "";  // Malformed: why (a string literal)
};

// Bytes in, events out: splits the stream into bounded lines and decodes them. Pure apart from
// its own fixed buffer; no allocation.
class BoardLineParser {
 public:
  // Feeds bytes; calls emit(const BoardEvent&) for every complete line (Line or Malformed) with
  // the event's tS set to tS. Blank lines are skipped without an event.
  template <class Emit>
  void feed(const char* data, std::size_t size, double tS, Emit&& emit) {
    for (std::size_t i = 0; i < size; ++i) {
      const char c = data[i];
      if (c == '\n') {
        BoardEvent e;
        if (finishLine(e)) {
          e.tS = tS;
          emit(static_cast<const BoardEvent&>(e));
        }
        continue;
      }
      if (length_ < line_.size()) {
        line_[length_++] = c;
      } else {
        overlong_ = true;
      }
    }
  }
  // Decodes one line (without its newline). False for a blank line (no event).
  static bool decodeLine(const char* line, std::size_t size, BoardEvent& event);
  // Forgets a partial line (after the port was opened again).
  void reset() {
    length_ = 0;
    overlong_ = false;
  }
  std::uint64_t lines() const { return lines_; }
  std::uint64_t malformed() const { return malformed_; }

 private:
  bool finishLine(BoardEvent& e);
  std::array<char, kMaxBoardLineBytes> line_{};
  std::size_t length_ = 0;
  bool overlong_ = false;
  std::uint64_t lines_ = 0, malformed_ = 0;
};

struct ButtonBoardOptions {
  int baud = 9600;
  double silentS = 0.5;       // silent this long: disconnected
  double reopenEveryS = 0.1;  // a port that went away is tried again this often
  std::uint32_t drillButtonMask = 1;
  double drillPedalAbove = 0.5;  // the pedal past half way drills too
};

// Events kept for a monitor that has not read them yet; past this they are counted dropped.
inline constexpr std::size_t kBoardEventCapacity = 4096;

class ButtonBoardDevice final : public Device {
 public:
  // Opens the port (InputError naming the device when it cannot) and starts its reader thread.
  ButtonBoardDevice(const std::string& name, const std::string& port,
                    const ButtonBoardOptions& options = {});
  ~ButtonBoardDevice() override;
  Capabilities capabilities() const override;
  // Buttons, pedal (0..1), knob (counts summed), drill trigger; no pose. tS is when the
  // newest line arrived.
  void poll(double nowS, DeviceSample& sample) noexcept override;
  // Every event in order (lines, malformed lines, disconnects, reconnects), for a monitor;
  // from one thread. False when there is none now.
  bool nextEvent(BoardEvent& event) noexcept;
  std::uint64_t lines() const { return lines_.load(std::memory_order_relaxed); }
  std::uint64_t malformed() const { return malformed_.load(std::memory_order_relaxed); }
  std::uint64_t eventsDropped() const { return eventsDropped_.load(std::memory_order_relaxed); }
  bool connected() const { return connected_.load(std::memory_order_relaxed); }

 private:
  struct State {
    std::uint32_t buttons = 0;
    int pedal = 0;
    std::int64_t knob = 0;
    bool connected = true;
    std::uint64_t lines = 0;
  };
  void readLoop();
  void push(const BoardEvent& event) noexcept;

  std::string port_;
  ButtonBoardOptions options_;
  SerialPort serial_;
  core::TripleBuffer<State> state_;
  std::uint64_t polledLines_ = 0;
  double polledAtS_ = -1.0;
  core::SpscRing<BoardEvent, kBoardEventCapacity> events_;
  std::atomic<std::uint64_t> lines_{0}, malformed_{0}, eventsDropped_{0};
  std::atomic<bool> connected_{true};
  std::atomic<bool> stop_{false};
  std::thread reader_;
};

}  // namespace osteon::devices
