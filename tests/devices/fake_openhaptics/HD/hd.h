/* A stand-in for OpenHaptics' <HD/hd.h>, for tests only: the types, constants and functions
   devices/src/touch_device.cpp uses, with the SDK's names and shapes (the values of the
   constants are this fake's own). tests/devices/fake_openhaptics/fake_hd.cpp implements them
   by recording every call and running the servo callback when a test asks, so the Touch's
   use of the HD API is checked on a machine without the SDK or the arm. */
#ifndef OSTEON_FAKE_HD_H
#define OSTEON_FAKE_HD_H

#ifdef __cplusplus
extern "C" {
#endif

typedef unsigned int HHD;
typedef unsigned int HDenum;
typedef int HDint;
typedef double HDdouble;
typedef unsigned int HDerror;
typedef const char* HDstring;
typedef unsigned int HDCallbackCode;
typedef unsigned long HDSchedulerHandle;
typedef unsigned short HDushort;

#define HDCALLBACK
typedef HDCallbackCode(HDCALLBACK* HDSchedulerCallback)(void* pUserData);

typedef struct {
  HDerror errorCode;
  int internalErrorCode;
  HHD hHD;
} HDErrorInfo;

#define HD_SUCCESS 0x0000
#define HD_DEVICE_INITIALIZATION_FAILED 0x0301
#define HD_COMM_ERROR 0x0302
#define HD_DEVICE_ERROR(X) (((X).errorCode) != HD_SUCCESS)
#define HD_DEFAULT_DEVICE 0
#define HD_INVALID_HANDLE 0xFFFFFFFF

#define HD_CALLBACK_DONE 0
#define HD_CALLBACK_CONTINUE 1
#define HD_MAX_SCHEDULER_PRIORITY 0xffff

#define HD_CURRENT_BUTTONS 0x2000
#define HD_CURRENT_POSITION 0x2050
#define HD_CURRENT_TRANSFORM 0x2052
#define HD_CURRENT_FORCE 0x2700
#define HD_FORCE_OUTPUT 0x4000
#define HD_DEVICE_BUTTON_1 (1 << 0)
#define HD_DEVICE_BUTTON_2 (1 << 1)

HHD hdInitDevice(HDstring pConfigName);
void hdDisableDevice(HHD hHD);
void hdMakeCurrentDevice(HHD hHD);
void hdEnable(HDenum cap);
HDErrorInfo hdGetError(void);
HDstring hdGetErrorString(HDerror errorCode);
void hdStartScheduler(void);
void hdStopScheduler(void);
HDSchedulerHandle hdScheduleAsynchronous(HDSchedulerCallback pCallback, void* pUserData,
                                         HDushort nPriority);
void hdUnschedule(HDSchedulerHandle hHandle);
void hdBeginFrame(HHD hHD);
void hdEndFrame(HHD hHD);
void hdGetDoublev(HDenum pname, HDdouble* params);
void hdGetIntegerv(HDenum pname, HDint* params);
void hdSetDoublev(HDenum pname, const HDdouble* params);

#ifdef __cplusplus
}
#endif

#endif
