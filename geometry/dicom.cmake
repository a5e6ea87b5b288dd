# DICOM and MetaImage volumes (src/io/volume_readers.h). GDCM is linked only by the
# libosteon_dicom.so plugin (plugin/): its static initialisers (the DICOM dictionaries) cost
# about 40 ms at the start of every program that links it, so osteon::geometry dlopen()s the
# plugin the first time a DICOM volume is read, as osteon::image does OpenImageIO.
#
# GDCM's CMake quirks on Debian (libgdcm-dev 3.0): find_package(GDCM) imports targets for the
# gdcm command-line tools (gdcmdump, gdcmconv, ...), which libgdcm-tools installs, not
# libgdcm-dev, and prints a warning per missing tool at every configure; its GDCM_LIBRARIES is
# empty. So the libraries are found by name here, under the include folder GDCM's config names.
include(GNUInstallDirs)
find_path(GDCM_INCLUDE_DIR gdcmImageReader.h PATH_SUFFIXES gdcm-3.0 REQUIRED)
foreach(_lib gdcmMSFF gdcmDICT gdcmDSED gdcmCommon)
  find_library(GDCM_${_lib}_LIBRARY ${_lib} REQUIRED)
  list(APPEND _osteon_gdcm_libraries ${GDCM_${_lib}_LIBRARY})
endforeach()
add_library(osteon_gdcm INTERFACE)
target_include_directories(osteon_gdcm SYSTEM INTERFACE ${GDCM_INCLUDE_DIR})
target_link_libraries(osteon_gdcm INTERFACE ${_osteon_gdcm_libraries})

add_library(osteon_dicom MODULE plugin/dicom_plugin.cpp plugin/dicom_decode.cpp plugin/dicom_series.cpp
                                plugin/dicom_stack.cpp plugin/dicom_walk.cpp)
target_include_directories(osteon_dicom PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/src/io
                                                ${PROJECT_SOURCE_DIR}/core/include)
target_link_libraries(osteon_dicom PRIVATE osteon_gdcm Threads::Threads)
set_target_properties(osteon_dicom PROPERTIES CXX_VISIBILITY_PRESET hidden VISIBILITY_INLINES_HIDDEN ON)
if(NOT (OSTEON_SANITIZE AND CMAKE_CXX_COMPILER_ID MATCHES "Clang"))
  target_link_options(osteon_dicom PRIVATE -Wl,--no-undefined)
endif()
osteon_target_warnings(osteon_dicom)
install(TARGETS osteon_dicom LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})

target_sources(osteon_geometry PRIVATE src/io/volume_readers.cpp src/io/metaimage_io.cpp
                                       src/io/dicom_volume.cpp src/io/dicom_child.cpp)
target_link_libraries(osteon_geometry PRIVATE ${CMAKE_DL_LIBS})
file(RELATIVE_PATH _osteon_bin_to_lib "${CMAKE_INSTALL_FULL_BINDIR}" "${CMAKE_INSTALL_FULL_LIBDIR}")
if(_osteon_bin_to_lib STREQUAL "")
  set(_osteon_bin_to_lib ".")
endif()
set_property(SOURCE src/io/dicom_volume.cpp APPEND PROPERTY COMPILE_DEFINITIONS
  OSTEON_DICOM_PLUGIN_NAME="$<TARGET_FILE_NAME:osteon_dicom>"
  OSTEON_DICOM_BUILD_DIR="$<TARGET_FILE_DIR:osteon_dicom>"
  OSTEON_DICOM_INSTALL_RELATIVE_LIBDIR="${_osteon_bin_to_lib}"
  OSTEON_DICOM_INSTALL_LIBDIR="${CMAKE_INSTALL_FULL_LIBDIR}")
# Whatever links osteon::geometry gets the plugin built with it.
add_dependencies(osteon_geometry osteon_dicom)
