# Sanitizer builds of osteon's own code (docs/architecture.md, "Sanitizer builds"):
#   cmake -S . -B build-asan -DOSTEON_SANITIZE=address,undefined -DCMAKE_BUILD_TYPE=RelWithDebInfo
#   cmake -S . -B build-tsan -DOSTEON_SANITIZE=thread            -DCMAKE_BUILD_TYPE=RelWithDebInfo
# or simply `scripts/test --sanitize address,undefined` / `scripts/test --sanitize thread`.
#
# Included by the top-level CMakeLists.txt before any module, so the flags reach every target
# of ours (modules, the image plugin, cli, tests, benchmarks) and nothing else: third-party
# libraries come from Debian, prebuilt and not instrumented. What their frames report is
# suppressed, entry by entry with its reason, in tests/sanitizers/*.supp.
#
# A finding fails the test that made it: ASan and TSan exit non-zero (TSan at exit, after
# printing every race), UBSan aborts on the first finding (-fno-sanitize-recover).
#
# OSTEON_SLOW_BUILD=1 is defined for every target of ours: tests that count 1 kHz periods a
# real-time thread managed in wall-clock time expect fewer of them under a sanitizer's 2-15x
# slowdown. Nothing else may depend on it.
set(OSTEON_SANITIZE "" CACHE STRING
    "Sanitizers for osteon's own targets: address,undefined | thread | empty for none")

if(NOT OSTEON_SANITIZE)
  # Called by tests/CMakeLists.txt; nothing to add without sanitizers.
  function(osteon_sanitizer_test_environment)
  endfunction()
  return()
endif()

if(NOT CMAKE_CXX_COMPILER_ID MATCHES "GNU|Clang")
  message(FATAL_ERROR "OSTEON_SANITIZE needs GCC or Clang, not ${CMAKE_CXX_COMPILER_ID}")
endif()
string(REPLACE "," ";" _osteon_sanitizers "${OSTEON_SANITIZE}")
list(REMOVE_DUPLICATES _osteon_sanitizers)
foreach(_s IN LISTS _osteon_sanitizers)
  if(NOT _s MATCHES "^(address|undefined|thread|leak)$")
    message(FATAL_ERROR "OSTEON_SANITIZE: unknown sanitizer '${_s}' "
                        "(address, undefined, leak or thread, comma separated)")
  endif()
endforeach()
if("thread" IN_LIST _osteon_sanitizers AND
   ("address" IN_LIST _osteon_sanitizers OR "leak" IN_LIST _osteon_sanitizers))
  message(FATAL_ERROR "OSTEON_SANITIZE: thread cannot be combined with address or leak")
endif()
list(JOIN _osteon_sanitizers "," _osteon_sanitize_list)
set(OSTEON_SANITIZE_FLAGS -fsanitize=${_osteon_sanitize_list} -fno-omit-frame-pointer -g)
if("undefined" IN_LIST _osteon_sanitizers)
  list(APPEND OSTEON_SANITIZE_FLAGS -fno-sanitize-recover=undefined)
endif()
message(STATUS "osteon: sanitizers ${_osteon_sanitize_list} on osteon's own targets "
               "(${CMAKE_BUILD_TYPE})")

add_compile_options(${OSTEON_SANITIZE_FLAGS})
add_link_options(-fsanitize=${_osteon_sanitize_list})
add_compile_definitions(OSTEON_SLOW_BUILD=1)

# Our static libraries hold instrumented code, so whatever links them needs the sanitizer's
# run-time library: the installed package passes the flag on (the `package` test builds
# examples/drill_minimal against it). Deferred to the end of the top-level directory, when
# every target exists; install(EXPORT) reads the property at generate time.
function(_osteon_sanitize_static_libraries dir)
  get_property(targets DIRECTORY "${dir}" PROPERTY BUILDSYSTEM_TARGETS)
  foreach(target IN LISTS targets)
    get_target_property(type ${target} TYPE)
    if(type STREQUAL "STATIC_LIBRARY")
      target_link_options(${target} INTERFACE -fsanitize=${_osteon_sanitize_list})
    endif()
  endforeach()
  get_property(subdirs DIRECTORY "${dir}" PROPERTY SUBDIRECTORIES)
  foreach(subdir IN LISTS subdirs)
    _osteon_sanitize_static_libraries("${subdir}")
  endforeach()
endfunction()
cmake_language(DEFER DIRECTORY "${CMAKE_SOURCE_DIR}"
               CALL _osteon_sanitize_static_libraries "${CMAKE_SOURCE_DIR}")

# TSan: oneTBB (and Embree on it) run on the calling thread only, so the synchronisation TSan
# cannot see inside Debian's uninstrumented libtbb.so makes no false reports; TSan checks
# osteon's own threads. Why and what it costs: tests/sanitizers/tsan_serial_tbb.cpp.
function(_osteon_tsan_serial_tbb)
  target_sources(osteon_geometry PRIVATE "${PROJECT_SOURCE_DIR}/tests/sanitizers/tsan_serial_tbb.cpp")
  target_link_options(osteon_geometry INTERFACE "LINKER:--undefined=osteon_tsan_serial_tbb")
endfunction()
if("thread" IN_LIST _osteon_sanitizers)
  cmake_language(DEFER DIRECTORY "${CMAKE_SOURCE_DIR}" CALL _osteon_tsan_serial_tbb)
endif()

# The run-time options every test runs with: halt on the first ASan error, leaks checked at
# exit, UBSan stack traces, and the suppression files (third-party frames only).
# intercept_tls_get_addr=0: the runtimes of GCC up to 13 and LLVM up to 16 take a dynamic TLS
# block whose start lies 16 bytes into a page for a pre-2.25 glibc one and read a bogus range
# before it; LeakSanitizer's tracer then dies at exit ("Tracer caught signal 11", exit 1, no
# leak named), at random, in processes that dlopen TLS-using libraries (the image plugin's
# OpenImageIO). google/sanitizers#1322.
set(_osteon_supp "${PROJECT_SOURCE_DIR}/tests/sanitizers")
set(_osteon_asan "halt_on_error=1:check_initialization_order=1:strict_init_order=1:intercept_tls_get_addr=0:suppressions=${_osteon_supp}/asan.supp")
set(_osteon_other_options
  "LSAN_OPTIONS=suppressions=${_osteon_supp}/lsan.supp:print_suppressions=0"
  "UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1:suppressions=${_osteon_supp}/ubsan.supp"
  "TSAN_OPTIONS=halt_on_error=0:second_deadlock_stack=1:history_size=7:suppressions=${_osteon_supp}/tsan.supp")
set(OSTEON_SANITIZER_ENVIRONMENT "ASAN_OPTIONS=${_osteon_asan}:detect_leaks=1" ${_osteon_other_options})
# Test programs whose tests run without LeakSanitizer (ASan and UBSan stay on), each with why:
#   osteon_viewer_tests: osteon-viewer draws with Mesa's llvmpipe under Xvfb, and glfwTerminate
#     unloads the driver (swrast_dri.so) before LSan's check at exit; what the driver still held
#     is then reported as leaked from "<unknown module>", which no suppression can name.
set(OSTEON_SANITIZER_NO_LEAK_CHECK osteon_viewer_tests)
set(_osteon_env_no_leaks "ASAN_OPTIONS=${_osteon_asan}:detect_leaks=0" ${_osteon_other_options})
# Per-test time limit in sanitizer builds, for every test (Release: 300 s, the package 600 s).
set(OSTEON_SANITIZER_TEST_TIMEOUT 1800)
# The same lines for a shell (`set -a; . BUILD/sanitizer.env; set +a`), to run osteon by hand.
list(JOIN OSTEON_SANITIZER_ENVIRONMENT "\n" _osteon_env_lines)
file(WRITE "${PROJECT_BINARY_DIR}/sanitizer.env" "${_osteon_env_lines}\n")

# Called from tests/CMakeLists.txt: every test of that folder, those gtest_discover_tests
# finds after the build included, gets OSTEON_SANITIZER_ENVIRONMENT and the longer time limit.
# (gtest_discover_tests' PROPERTIES cannot carry a list-valued ENVIRONMENT in CMake 3.25, so this
# ctest include file, read after the discovered tests', sets it.)
function(osteon_sanitizer_test_environment)
  # Deferred to the end of the calling folder, so tests added below the call are covered too.
  cmake_language(DEFER CALL _osteon_sanitizer_test_environment)
endfunction()
function(_osteon_sanitizer_test_environment)
  get_property(targets DIRECTORY PROPERTY BUILDSYSTEM_TARGETS)
  get_property(tests DIRECTORY PROPERTY TESTS)
  if(tests)  # add_test ones exist now (ctest's include files run before their add_test lines)
    set_tests_properties(${tests} PROPERTIES TIMEOUT ${OSTEON_SANITIZER_TEST_TIMEOUT}
                                             ENVIRONMENT "${OSTEON_SANITIZER_ENVIRONMENT}")
  endif()
  set(script "# Generated by cmake/OsteonSanitizers.cmake\n")
  foreach(target IN LISTS targets)
    set(environment "${OSTEON_SANITIZER_ENVIRONMENT}")
    if(target IN_LIST OSTEON_SANITIZER_NO_LEAK_CHECK)
      set(environment "${_osteon_env_no_leaks}")
    endif()
    # ${target}_TESTS is set by the target's discovery include. One bracket argument holds the
    # whole list (its semicolons are not split). A sanitizer's slowdown is not a hang: every
    # test gets OSTEON_SANITIZER_TEST_TIMEOUT.
    string(APPEND script "if(${target}_TESTS)\n"
                         "  set_tests_properties(\${${target}_TESTS} PROPERTIES\n"
                         "    TIMEOUT ${OSTEON_SANITIZER_TEST_TIMEOUT}\n"
                         "    ENVIRONMENT [==[${environment}]==])\n"
                         "endif()\n")
  endforeach()
  set(file "${CMAKE_CURRENT_BINARY_DIR}/osteon_sanitizer_environment.cmake")
  file(WRITE "${file}" "${script}")
  set_property(DIRECTORY APPEND PROPERTY TEST_INCLUDE_FILES "${file}")
endfunction()
