// The fake HD API's controls for tests: what was called, the arm's state, the servo loop.
#pragma once

#include <HD/hd.h>
#include <string>
#include <vector>

namespace fake_hd {

struct Arm {
  std::vector<std::string> calls;  // "hdInitDevice(default)", "hdEnable(HD_FORCE_OUTPUT)", ...
  HDdouble transform[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  HDint buttons = 0;
  HDdouble force[3] = {0, 0, 0};   // the last force set
  HDerror failInit = HD_SUCCESS;   // hdInitDevice's error, if any
  HDerror failStart = HD_SUCCESS;  // hdStartScheduler's error, if any
  HDSchedulerCallback callback = nullptr;
  void* user = nullptr;
  bool running = false;
  HDerror pending = HD_SUCCESS;
};

Arm& arm();
void reset();
// Runs the scheduled callback `ticks` times, as the servo thread would; returns how many ran
// (the callback may stop it).
int runServo(int ticks);
// The calls made since the last take.
std::vector<std::string> takeCalls();

}  // namespace fake_hd
