// The fake HD API behind tests/devices/fake_openhaptics/HD/hd.h: records each call, keeps one
// arm's state, runs the servo callback when the test asks.
#include "fake_hd.h"

#include <string>

namespace fake_hd {

Arm& arm() {
  static Arm a;
  return a;
}

void reset() {
  arm() = Arm{};
}

int runServo(int ticks) {
  Arm& a = arm();
  int ran = 0;
  for (; ran < ticks && a.running && a.callback; ++ran) {
    if (a.callback(a.user) == HD_CALLBACK_DONE) {
      a.callback = nullptr;
      ++ran;
      break;
    }
  }
  return ran;
}

std::vector<std::string> takeCalls() {
  std::vector<std::string> calls;
  calls.swap(arm().calls);
  return calls;
}

namespace {

std::string name(HDenum e) {
  switch (e) {
    case HD_CURRENT_BUTTONS:
      return "HD_CURRENT_BUTTONS";
    case HD_CURRENT_POSITION:
      return "HD_CURRENT_POSITION";
    case HD_CURRENT_TRANSFORM:
      return "HD_CURRENT_TRANSFORM";
    case HD_CURRENT_FORCE:
      return "HD_CURRENT_FORCE";
    case HD_FORCE_OUTPUT:
      return "HD_FORCE_OUTPUT";
    default:
      return "0x" + std::to_string(e);
  }
}

}  // namespace

}  // namespace fake_hd

using fake_hd::arm;

extern "C" {

HHD hdInitDevice(HDstring config) {
  arm().calls.push_back(std::string("hdInitDevice(") + (config ? config : "default") + ")");
  if (arm().failInit != HD_SUCCESS) {
    arm().pending = arm().failInit;
    return HD_INVALID_HANDLE;
  }
  return 7;
}
void hdDisableDevice(HHD h) {
  arm().calls.push_back("hdDisableDevice(" + std::to_string(h) + ")");
}
void hdMakeCurrentDevice(HHD h) {
  arm().calls.push_back("hdMakeCurrentDevice(" + std::to_string(h) + ")");
}
void hdEnable(HDenum cap) {
  arm().calls.push_back("hdEnable(" + fake_hd::name(cap) + ")");
}
HDErrorInfo hdGetError(void) {
  arm().calls.push_back("hdGetError");
  HDErrorInfo e{arm().pending, 0, 7};
  arm().pending = HD_SUCCESS;
  return e;
}
HDstring hdGetErrorString(HDerror code) {
  return code == HD_DEVICE_INITIALIZATION_FAILED ? "Device Initialization Failed"
                                                 : "Communication Error";
}
void hdStartScheduler(void) {
  arm().calls.push_back("hdStartScheduler");
  if (arm().failStart != HD_SUCCESS) {
    arm().pending = arm().failStart;
    return;
  }
  arm().running = true;
}
void hdStopScheduler(void) {
  arm().calls.push_back("hdStopScheduler");
  arm().running = false;
}
HDSchedulerHandle hdScheduleAsynchronous(HDSchedulerCallback callback, void* user,
                                         HDushort priority) {
  arm().calls.push_back("hdScheduleAsynchronous(" +
                        std::string(priority == HD_MAX_SCHEDULER_PRIORITY ? "max" : "other") + ")");
  arm().callback = callback;
  arm().user = user;
  return 42;
}
void hdUnschedule(HDSchedulerHandle handle) {
  arm().calls.push_back("hdUnschedule(" + std::to_string(handle) + ")");
  arm().callback = nullptr;
}
void hdBeginFrame(HHD h) {
  arm().calls.push_back("hdBeginFrame(" + std::to_string(h) + ")");
}
void hdEndFrame(HHD h) {
  arm().calls.push_back("hdEndFrame(" + std::to_string(h) + ")");
}
void hdGetDoublev(HDenum pname, HDdouble* params) {
  arm().calls.push_back("hdGetDoublev(" + fake_hd::name(pname) + ")");
  if (pname == HD_CURRENT_TRANSFORM) {
    for (int i = 0; i < 16; ++i) params[i] = arm().transform[i];
  } else if (pname == HD_CURRENT_POSITION) {
    for (int i = 0; i < 3; ++i) params[i] = arm().transform[12 + i];
  }
}
void hdGetIntegerv(HDenum pname, HDint* params) {
  arm().calls.push_back("hdGetIntegerv(" + fake_hd::name(pname) + ")");
  if (pname == HD_CURRENT_BUTTONS) *params = arm().buttons;
}
void hdSetDoublev(HDenum pname, const HDdouble* params) {
  arm().calls.push_back("hdSetDoublev(" + fake_hd::name(pname) + ")");
  if (pname == HD_CURRENT_FORCE) {
    for (int i = 0; i < 3; ++i) arm().force[i] = params[i];
  }
}

}  // extern "C"
