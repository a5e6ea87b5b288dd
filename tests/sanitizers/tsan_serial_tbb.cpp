// TSan builds only (OSTEON_SANITIZE=thread): cmake/OsteonSanitizers.cmake compiles this into
// osteon::geometry and makes every program that links it keep it (-Wl,--undefined), so the
// tests, the osteon command and programs built on the installed package all run with it.
//
// Why: oneTBB's scheduler lives in Debian's libtbb.so, built without TSan. Handing a task to a
// worker, stealing it and joining it back go through atomics inside that library, which TSan
// never sees, so every access in a tbb::parallel_for body (and Embree's BVH build, which runs
// on TBB) is reported as racing with the code before and after the loop: hundreds of false
// reports per test, and not even stably suppressible (the worker's earlier accesses often have
// no stack left to match). With TBB limited to the calling thread those reports cannot arise,
// and TSan checks what osteon itself runs concurrently: the threaded runtime's haptic,
// collision and visual threads, their triple buffers and rings, and everything they call.
// The cost, stated in docs/architecture.md: TBB-parallel bodies are not race-checked by TSan
// (they run serially here; the ASan build still runs them in parallel).
#include <oneapi/tbb/global_control.h>

// Referenced by -Wl,--undefined=osteon_tsan_serial_tbb so a static link keeps this object.
extern "C" {
extern const int osteon_tsan_serial_tbb;
const int osteon_tsan_serial_tbb = 1;
}

namespace {
const oneapi::tbb::global_control gSerialTbb(oneapi::tbb::global_control::max_allowed_parallelism,
                                             1);
}  // namespace
