# The installable CMake package: `cmake --install BUILD --prefix P` gives P/include/osteon/...,
# P/lib/libosteon_*.a, P/bin/osteon and P/lib/cmake/osteon/{osteonConfig,osteonConfigVersion,
# osteonTargets}.cmake, so that an integrator writes
#   find_package(osteon REQUIRED)
#   target_link_libraries(app PRIVATE osteon::simulation)
# Every module made by osteon_add_module joins the export set `osteonTargets` under its short
# name (osteon_geometry is exported as osteon::geometry).
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(OSTEON_INSTALL_CMAKEDIR "${CMAKE_INSTALL_LIBDIR}/cmake/osteon"
    CACHE STRING "Where osteonConfig.cmake is installed, relative to the prefix")

# Called by osteon_add_module for every module: export it and install its public headers
# (<module>/include/osteon/<module>/..., .inl files included).
function(osteon_install_module name)
  set_target_properties(osteon_${name} PROPERTIES EXPORT_NAME ${name})
  install(TARGETS osteon_${name} EXPORT osteonTargets
          ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
          LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
  if(EXISTS "${CMAKE_CURRENT_SOURCE_DIR}/include")
    install(DIRECTORY "${CMAKE_CURRENT_SOURCE_DIR}/include/"
            DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
  endif()
  set_property(GLOBAL APPEND PROPERTY OSTEON_EXPORTED_MODULES osteon_${name})
endfunction()

# How an imported target our modules link is found again in osteonConfig.cmake. Static
# libraries export their PRIVATE links too (as $<LINK_ONLY:...>), so every one of them must
# exist in the consumer. The lines mirror the find_package calls in the top-level
# CMakeLists.txt and the modules' CMakeLists.txt; the order is the order they are found in.
set(_osteon_dependency_keys glm nlohmann_json embree OpenMesh TBB Threads ZLIB CGAL OpenImageIO hidapi serialport)
set(_osteon_dep_glm         "find_dependency(glm)")
# simulation reads exercises (JSON), header-only.
set(_osteon_dep_nlohmann_json "find_dependency(nlohmann_json 3)")
set(_osteon_dep_embree      "find_dependency(embree 3)")
# Debian's OpenMesh has no version file: no version, and CONFIG so CGAL's FindOpenMesh
# (on CMAKE_MODULE_PATH once CGAL is found) is not used instead.
set(_osteon_dep_OpenMesh    "find_dependency(OpenMesh CONFIG)")
set(_osteon_dep_TBB         "find_dependency(TBB CONFIG)")
set(_osteon_dep_Threads     "find_dependency(Threads)")
set(_osteon_dep_ZLIB        "find_dependency(ZLIB)")
set(_osteon_dep_CGAL        "find_dependency(CGAL 5.5)")
# As validation/CMakeLists.txt finds it: through pkg-config, not Debian's broken CMake package.
set(_osteon_dep_OpenImageIO [=[find_dependency(PkgConfig)
if(NOT TARGET PkgConfig::OpenImageIO)
  pkg_check_modules(OpenImageIO QUIET IMPORTED_TARGET OpenImageIO)
  if(NOT TARGET PkgConfig::OpenImageIO)
    set(osteon_FOUND FALSE)
    set(osteon_NOT_FOUND_MESSAGE "osteon needs OpenImageIO (pkg-config OpenImageIO), not found")
    return()
  endif()
endif()]=])

# As devices/CMakeLists.txt finds them: pkg-config (hidapi has no CMake package in Debian).
set(_osteon_dep_hidapi [=[find_dependency(PkgConfig)
if(NOT TARGET PkgConfig::HIDAPI)
  pkg_check_modules(HIDAPI QUIET IMPORTED_TARGET hidapi-hidraw)
  if(NOT TARGET PkgConfig::HIDAPI)
    set(osteon_FOUND FALSE)
    set(osteon_NOT_FOUND_MESSAGE "osteon needs hidapi (pkg-config hidapi-hidraw, Debian libhidapi-dev), not found")
    return()
  endif()
endif()]=])
set(_osteon_dep_serialport [=[find_dependency(PkgConfig)
if(NOT TARGET PkgConfig::SERIALPORT)
  pkg_check_modules(SERIALPORT QUIET IMPORTED_TARGET libserialport)
  if(NOT TARGET PkgConfig::SERIALPORT)
    set(osteon_FOUND FALSE)
    set(osteon_NOT_FOUND_MESSAGE "osteon needs libserialport (pkg-config libserialport, Debian libserialport-dev), not found")
    return()
  endif()
endif()]=])

function(_osteon_dependency_key item out)
  set(key "")
  if(item MATCHES "^glm(::|$)")
    set(key glm)
  elseif(item STREQUAL "nlohmann_json::nlohmann_json")
    set(key nlohmann_json)
  elseif(item STREQUAL "embree")
    set(key embree)
  elseif(item MATCHES "^OpenMesh")
    set(key OpenMesh)
  elseif(item MATCHES "^TBB::")
    set(key TBB)
  elseif(item STREQUAL "Threads::Threads")
    set(key Threads)
  elseif(item STREQUAL "ZLIB::ZLIB")
    set(key ZLIB)
  elseif(item MATCHES "^CGAL::")
    set(key CGAL)
  elseif(item STREQUAL "PkgConfig::OpenImageIO")
    set(key OpenImageIO)
  elseif(item STREQUAL "PkgConfig::HIDAPI")
    set(key hidapi)
  elseif(item STREQUAL "PkgConfig::SERIALPORT")
    set(key serialport)
  endif()
  set(${out} "${key}" PARENT_SCOPE)
endfunction()

# Called once at the end of the top-level CMakeLists.txt, after every module and the cli.
function(osteon_install_package)
  # The find_dependency lines the exported targets need, from what they actually link.
  # Walked transitively through our own targets (osteon::image, exported by image/, too).
  get_property(pending GLOBAL PROPERTY OSTEON_EXPORTED_MODULES)
  set(visited "")
  set(needed "")
  while(pending)
    list(POP_FRONT pending target)
    get_target_property(aliased ${target} ALIASED_TARGET)
    if(aliased)
      set(target ${aliased})
    endif()
    if(target IN_LIST visited)
      continue()
    endif()
    list(APPEND visited ${target})
    get_target_property(type ${target} TYPE)
    set(items "")
    if(NOT type STREQUAL "INTERFACE_LIBRARY")
      get_target_property(link ${target} LINK_LIBRARIES)
      if(link)
        list(APPEND items ${link})
      endif()
    endif()
    get_target_property(ilink ${target} INTERFACE_LINK_LIBRARIES)
    if(ilink)
      list(APPEND items ${ilink})
    endif()
    foreach(item IN LISTS items)
      string(REGEX REPLACE "^\\$<LINK_ONLY:(.*)>$" "\\1" item "${item}")
      _osteon_dependency_key("${item}" key)
      if(NOT key STREQUAL "")
        list(APPEND needed ${key})
        continue()
      endif()
      if(TARGET "${item}")
        get_target_property(imported "${item}" IMPORTED)
        if(NOT imported)
          list(APPEND pending "${item}")  # one of ours: exported with the rest, walk it too
          continue()
        endif()
      elseif(NOT item MATCHES "::")
        continue()  # a plain library name (dl) or flag: nothing to find
      endif()
      # An imported target (or one visible only in its module's folder, as
      # pkg_check_modules makes them) that we cannot find again.
      message(FATAL_ERROR
        "${target} links the imported target ${item}, which the installed osteon package "
        "does not know how to find again: add it to cmake/OsteonPackage.cmake "
        "(_osteon_dependency_keys and _osteon_dependency_key).")
    endforeach()
  endwhile()
  set(OSTEON_FIND_DEPENDENCIES "")
  foreach(key IN LISTS _osteon_dependency_keys)
    if(key IN_LIST needed)
      string(APPEND OSTEON_FIND_DEPENDENCIES "${_osteon_dep_${key}}\n")
    endif()
  endforeach()

  install(EXPORT osteonTargets NAMESPACE osteon:: FILE osteonTargets.cmake
          DESTINATION ${OSTEON_INSTALL_CMAKEDIR})
  configure_package_config_file(
    "${PROJECT_SOURCE_DIR}/cmake/osteonConfig.cmake.in"
    "${PROJECT_BINARY_DIR}/osteonConfig.cmake"
    INSTALL_DESTINATION ${OSTEON_INSTALL_CMAKEDIR})
  # 0.x: a minor version may break the API, so only the same major.minor is compatible.
  if(PROJECT_VERSION_MAJOR EQUAL 0)
    set(compatibility SameMinorVersion)
  else()
    set(compatibility SameMajorVersion)
  endif()
  write_basic_package_version_file("${PROJECT_BINARY_DIR}/osteonConfigVersion.cmake"
    VERSION ${PROJECT_VERSION} COMPATIBILITY ${compatibility})
  install(FILES "${PROJECT_BINARY_DIR}/osteonConfig.cmake"
                "${PROJECT_BINARY_DIR}/osteonConfigVersion.cmake"
          DESTINATION ${OSTEON_INSTALL_CMAKEDIR})

  # The image plugin osteon_image (OpenImageIO behind dlopen) is a MODULE library loaded at
  # run time, not linked: image/CMakeLists.txt installs it to the library folder, beside
  # osteon::image (its small static loader, in this export set because validation links it).
endfunction()
