// The C interface between osteon::geometry's DICOM loader (dicom_volume.cpp) and the
// libosteon_dicom.so plugin (geometry/plugin, the only code that links GDCM: GDCM's static
// initialisers cost about 40 ms at every start of a program that links it). Plain C types only;
// bump OSTEON_DICOM_ABI on any change here.
#pragma once

#include <stddef.h>

#define OSTEON_DICOM_ABI 2

#ifdef __cplusplus
extern "C" {
#endif

// A series as read: values of `type` ("uint8" "int8" "uint16" "int16" "uint32" "int32"
// "float"), slice after slice in stacking order, each row after row (x fastest).
typedef struct osteon_dicom_volume {
  int sizes[3];       // columns, rows, slices
  double m[3][3];     // m[r][axis]: LPS mm step along stored axis `axis` (r = L, P, S)
  double centre0[3];  // LPS mm centre of the first voxel
  char type[8];       // the stored scalar type
  double slope;       // HU = stored * slope + intercept (1, 0 when the values are HU)
  double intercept;
  int slices_rescaled;  // 1: slices had their own slope or intercept: values are float HU
  char series_uid[65];  // the Series Instance UID read, and its description (truncated)
  char series_description[129];
} osteon_dicom_volume;

// Where the values go: a buffer of `bytes` from the caller, or NULL when it refuses (too large
// for this machine's memory: the read stops, returning 3).
typedef void* (*osteon_dicom_alloc_fn)(void* context, size_t bytes);

// Called as the work advances, from any of the plugin's threads: after each file's header is
// checked and each slice decoded. `next_pixels`: how many pixels the next step decodes in one
// call (a multi-frame file's), 0 when it is one slice or less: the caller allows it the time.
typedef void (*osteon_dicom_progress_fn)(void* context, unsigned long long next_pixels);

typedef int (*osteon_dicom_abi_fn)(void);
typedef const char* (*osteon_dicom_library_version_fn)(void);
// Reads the CT series at `path` (a folder, or one file: a multi-frame image or a slice standing
// for its series in its folder); `series` picks a Series Instance UID ("": the one with most
// slices). Slices decode in parallel; `out` is filled before `alloc` is called. 0 on success;
// otherwise 2 (bad input) or 3 (the buffer refused), with a one-line reason in errbuf
// (truncated to errlen - 1 characters). alloc and progress (may be NULL) get `context`.
typedef int (*osteon_dicom_read_fn)(const char* path, const char* series, osteon_dicom_volume* out,
                                    osteon_dicom_alloc_fn alloc, osteon_dicom_progress_fn progress,
                                    void* context, char* errbuf, size_t errlen);
// The series at `path`, one line each: "UID<TAB>slices<TAB>description\n", in a buffer from
// alloc (NUL-terminated). 0 on success, else 2 with the reason in errbuf.
typedef int (*osteon_dicom_list_fn)(const char* path, osteon_dicom_alloc_fn alloc,
                                    osteon_dicom_progress_fn progress, void* context, char* errbuf,
                                    size_t errlen);

int osteon_dicom_abi(void);
const char* osteon_dicom_library_version(void);
int osteon_dicom_read(const char* path, const char* series, osteon_dicom_volume* out,
                      osteon_dicom_alloc_fn alloc, osteon_dicom_progress_fn progress, void* context,
                      char* errbuf, size_t errlen);
int osteon_dicom_list(const char* path, osteon_dicom_alloc_fn alloc,
                      osteon_dicom_progress_fn progress, void* context, char* errbuf,
                      size_t errlen);

#ifdef __cplusplus
}
#endif
