# Warnings as errors on osteon's own targets only; third-party headers come in as SYSTEM
# include directories through their imported targets, so their warnings do not stop us.
function(osteon_target_warnings target)
  # -Wconversion and -Wsign-conversion: a narrowing or a change of sign is written as a cast,
  # so the ones meant are visible and the others are errors.
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow
                                           -Wnon-virtual-dtor -Wcast-align
                                           -Wconversion -Wsign-conversion)
  if(OSTEON_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()

# One library per module: osteon_<name> with alias osteon::<name>, public headers in
# <module>/include/osteon/<module>/, private sources in <module>/src/. Needs OsteonPackage
# (included first by the top-level CMakeLists.txt) for the install and export rules.
function(osteon_add_module name)
  cmake_parse_arguments(ARG "" "" "SOURCES;PUBLIC_DEPS;PRIVATE_DEPS" ${ARGN})
  if(ARG_SOURCES)
    add_library(osteon_${name} STATIC ${ARG_SOURCES})
    target_include_directories(osteon_${name} PUBLIC
      $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
      $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
    target_link_libraries(osteon_${name} PUBLIC ${ARG_PUBLIC_DEPS} PRIVATE ${ARG_PRIVATE_DEPS})
    target_compile_features(osteon_${name} PUBLIC cxx_std_17)
    osteon_target_warnings(osteon_${name})
  else()
    add_library(osteon_${name} INTERFACE)
    target_include_directories(osteon_${name} INTERFACE
      $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
      $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
    target_link_libraries(osteon_${name} INTERFACE ${ARG_PUBLIC_DEPS})
    target_compile_features(osteon_${name} INTERFACE cxx_std_17)
  endif()
  add_library(osteon::${name} ALIAS osteon_${name})
  # Installed and exported as osteon::<name> (cmake/OsteonPackage.cmake).
  osteon_install_module(${name})
endfunction()
