#include "osteon/devices/button_board.h"

#include <chrono>

#include "osteon/core/error.h"

namespace osteon::devices {

namespace {

bool isHex(char c) {
  return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f') || (c >= 'A' && c <= 'F');
}
int hexValue(char c) {
  return c <= '9' ? c - '0' : (c | 0x20) - 'a' + 10;
}

bool reject(BoardEvent& e, const char* reason) {
  e.kind = BoardEvent::Kind::Malformed;
  e.reason = reason;
  return true;
}

}  // namespace

bool BoardLineParser::decodeLine(const char* line, std::size_t size, BoardEvent& e) {
  while (size > 0 && line[size - 1] == '\r') --size;
  if (size == 0) return false;
  e = BoardEvent{};
  for (std::size_t i = 0; i < size; ++i) {
    const auto c = static_cast<unsigned char>(line[i]);
    if (c < 0x20 || c > 0x7e) return reject(e, "a byte that is not printable ASCII");
  }
  bool haveB = false, haveP = false;
  std::size_t start = 0;
  while (start <= size) {
    std::size_t end = start;
    while (end < size && line[end] != ',') ++end;
    const char* field = line + start;
    const std::size_t length = end - start;
    std::size_t eq = 0;
    while (eq < length && field[eq] != '=') ++eq;
    if (eq == length) return reject(e, "a field without '=' (expected KEY=VALUE)");
    if (eq == 0) return reject(e, "a field without a key");
    const char* value = field + eq + 1;
    const std::size_t valueLength = length - eq - 1;
    if (eq == 1 && field[0] == 'B') {
      if (haveB) return reject(e, "B given twice");
      if (valueLength == 0 || valueLength > 8)
        return reject(e, "B is not a hex button mask (1 to 8 hex digits)");
      std::uint32_t mask = 0;
      for (std::size_t i = 0; i < valueLength; ++i) {
        if (!isHex(value[i])) return reject(e, "B is not a hex button mask (1 to 8 hex digits)");
        mask = mask << 4 | std::uint32_t(hexValue(value[i]));
      }
      e.buttons = mask;
      haveB = true;
    } else if (eq == 1 && field[0] == 'P') {
      if (haveP) return reject(e, "P given twice");
      if (valueLength == 0 || valueLength > 4) return reject(e, "P is not a pedal value 0-1023");
      int pedal = 0;
      for (std::size_t i = 0; i < valueLength; ++i) {
        if (value[i] < '0' || value[i] > '9') return reject(e, "P is not a pedal value 0-1023");
        pedal = pedal * 10 + (value[i] - '0');
      }
      if (pedal > kBoardPedalMax) return reject(e, "P is not a pedal value 0-1023");
      e.pedal = pedal;
      haveP = true;
    } else if (eq == 1 && field[0] == 'K') {
      if (e.hasKnob) return reject(e, "K given twice");
      std::size_t i = 0;
      bool negative = false;
      if (i < valueLength && (value[i] == '-' || value[i] == '+')) negative = value[i++] == '-';
      if (i == valueLength || valueLength - i > 10)
        return reject(e, "K is not a signed integer (up to 10 digits)");
      std::int64_t knob = 0;
      for (; i < valueLength; ++i) {
        if (value[i] < '0' || value[i] > '9')
          return reject(e, "K is not a signed integer (up to 10 digits)");
        knob = knob * 10 + (value[i] - '0');
      }
      e.knob = negative ? -knob : knob;
      e.hasKnob = true;
    }
    // Any other key is ignored: a later board may send more.
    start = end + 1;
  }
  if (!haveB) return reject(e, "B (the button mask) is missing");
  if (!haveP) return reject(e, "P (the pedal) is missing");
  e.kind = BoardEvent::Kind::Line;
  return true;
}

bool BoardLineParser::finishLine(BoardEvent& e) {
  const bool overlong = overlong_;
  const std::size_t length = length_;
  reset();
  if (overlong) {
    ++malformed_;
    e = BoardEvent{};
    return reject(e, "line longer than 256 bytes");
  }
  if (!decodeLine(line_.data(), length, e)) return false;
  if (e.kind == BoardEvent::Kind::Line) {
    ++lines_;
  } else {
    ++malformed_;
  }
  return true;
}

// ---- the device ----

ButtonBoardDevice::ButtonBoardDevice(const std::string& name, const std::string& port,
                                     const ButtonBoardOptions& options)
    : Device(name),
      port_(port),
      options_(options),
      serial_(SerialPort::open(port, options.baud, name)) {
  reader_ = std::thread([this] { readLoop(); });
}

ButtonBoardDevice::~ButtonBoardDevice() {
  stop_.store(true);
  if (reader_.joinable()) reader_.join();
}

Capabilities ButtonBoardDevice::capabilities() const {
  Capabilities c;
  c.buttons = true;
  c.pedal = true;
  c.knob = true;
  return c;
}

void ButtonBoardDevice::push(const BoardEvent& event) noexcept {
  if (!events_.push(event)) eventsDropped_.fetch_add(1, std::memory_order_relaxed);
}

bool ButtonBoardDevice::nextEvent(BoardEvent& event) noexcept {
  return events_.pop(event);
}

void ButtonBoardDevice::readLoop() {
  using Clock = std::chrono::steady_clock;
  const Clock::time_point start = Clock::now();
  const auto now = [&] { return std::chrono::duration<double>(Clock::now() - start).count(); };
  BoardLineParser parser;
  State state;
  double lastByteS = 0.0;
  double lastTryS = 0.0;
  bool connected = true;
  const auto setConnected = [&](bool on, double t) {
    connected = on;
    connected_.store(on, std::memory_order_relaxed);
    state.connected = on;
    state_.write(state);
    BoardEvent e;
    e.kind = on ? BoardEvent::Kind::Connected : BoardEvent::Kind::Disconnected;
    e.tS = t;
    push(e);
  };
  const auto onEvent = [&](const BoardEvent& e) {
    if (e.kind == BoardEvent::Kind::Line) {
      state.buttons = e.buttons;
      state.pedal = e.pedal;
      state.knob += e.knob;
      ++state.lines;
      state_.write(state);
      lines_.fetch_add(1, std::memory_order_relaxed);
    } else {
      malformed_.fetch_add(1, std::memory_order_relaxed);
    }
    push(e);
  };
  char buf[512];
  while (!stop_.load(std::memory_order_relaxed)) {
    if (!serial_.isOpen()) {
      const double t = now();
      if (t - lastTryS >= options_.reopenEveryS) {
        lastTryS = t;
        serial_ = SerialPort::tryOpen(port_, options_.baud);
        if (serial_.isOpen()) {
          parser.reset();
          continue;
        }
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
      continue;
    }
    const int n = serial_.read(buf, sizeof buf, 50);
    const double t = now();
    if (n > 0) {
      lastByteS = t;
      if (!connected) setConnected(true, t);
      parser.feed(buf, std::size_t(n), t, onEvent);
    } else if (n < 0) {
      // Hung up or unplugged: gone now, whatever the silence timer says.
      lastTryS = t;
      if (connected) setConnected(false, t);
    } else if (connected && t - lastByteS > options_.silentS) {
      setConnected(false, t);
    }
  }
}

void ButtonBoardDevice::poll(double nowS, DeviceSample& sample) noexcept {
  const State s = state_.read();
  if (s.lines != polledLines_) {
    polledLines_ = s.lines;
    polledAtS_ = nowS;
  }
  sample.tS = polledAtS_;
  sample.buttons = s.buttons;
  sample.pedal = double(s.pedal) / double(kBoardPedalMax);
  sample.knob = s.knob;
  sample.drillOn =
      (s.buttons & options_.drillButtonMask) != 0 || sample.pedal > options_.drillPedalAbove;
  sample.connected = s.connected;
}

}  // namespace osteon::devices
