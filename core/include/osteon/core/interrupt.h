// SIGINT and SIGTERM during a run that writes a folder: the handler only records the signal;
// the runs' loops poll interrupted() and stop, and the command throws Interrupted, so the run
// ends cleanly (its folder keeps its previous outputs) with exit 128 + signal (130, 143).
#pragma once

#include <atomic>
#include <csignal>
#include <signal.h>
#include <stdexcept>
#include <string>

namespace osteon {

// The signal caught, 0 for none. Lock-free, so the handler may store it.
inline std::atomic<int> gInterruptSignal{0};

inline bool interrupted() noexcept {
  return gInterruptSignal.load(std::memory_order_relaxed) != 0;
}

// A run stopped by SIGINT or SIGTERM: what() is one line; the exit code is 128 + the signal.
class Interrupted : public std::runtime_error {
 public:
  explicit Interrupted(int signal)
      : std::runtime_error(std::string("interrupted by ") +
                           (signal == SIGINT ? "SIGINT" : "SIGTERM")),
        signal_(signal) {}
  int exitCode() const { return 128 + signal_; }

 private:
  int signal_;
};

inline void throwIfInterrupted() {
  const int signal = gInterruptSignal.load(std::memory_order_relaxed);
  if (signal != 0) throw Interrupted(signal);
}

extern "C" inline void osteonRecordInterrupt(int signal) {
  int none = 0;
  // The first signal asks the run to stop; a second one (a run that does not poll yet, as in a
  // long voxelization) takes the default action at once. Only async-signal-safe calls here.
  if (!gInterruptSignal.compare_exchange_strong(none, signal)) {
    std::signal(signal, SIG_DFL);
    std::raise(signal);
  }
}

// While alive, SIGINT and SIGTERM are recorded instead of ending the process; the previous
// handlers come back when it ends.
class InterruptScope {
 public:
  InterruptScope() {
    struct sigaction action {};
    action.sa_handler = osteonRecordInterrupt;
    action.sa_flags = SA_RESTART;  // writes and waits go on; the loops see the flag
    sigemptyset(&action.sa_mask);
    sigaction(SIGINT, &action, &oldInt_);
    sigaction(SIGTERM, &action, &oldTerm_);
  }
  ~InterruptScope() {
    sigaction(SIGINT, &oldInt_, nullptr);
    sigaction(SIGTERM, &oldTerm_, nullptr);
  }
  InterruptScope(const InterruptScope&) = delete;
  InterruptScope& operator=(const InterruptScope&) = delete;

 private:
  struct sigaction oldInt_ {};
  struct sigaction oldTerm_ {};
};

}  // namespace osteon
