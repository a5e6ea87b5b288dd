# OpenIGTLink (Debian libopenigtlink-dev 1.11, protocol 2) as the one imported target
# OpenIGTLink::OpenIGTLink. Its CMake config sets only the old-style OpenIGTLink_INCLUDE_DIRS
# and OpenIGTLink_LIBRARIES (a bare "OpenIGTLink" to be found in OpenIGTLink_LIBRARY_DIRS), no
# imported target: they are wrapped here, once, so that every user links a target and gets the
# headers as system includes (they do not build clean under our warnings).
if(NOT TARGET OpenIGTLink::OpenIGTLink)
  find_package(OpenIGTLink REQUIRED CONFIG)
  find_library(OSTEON_OPENIGTLINK_LIBRARY NAMES ${OpenIGTLink_LIBRARIES}
               HINTS ${OpenIGTLink_LIBRARY_DIRS} REQUIRED)
  add_library(OpenIGTLink::OpenIGTLink INTERFACE IMPORTED GLOBAL)  # tests and fuzzers link it too
  set_target_properties(OpenIGTLink::OpenIGTLink PROPERTIES
    INTERFACE_INCLUDE_DIRECTORIES "${OpenIGTLink_INCLUDE_DIRS}"
    INTERFACE_LINK_LIBRARIES "${OSTEON_OPENIGTLINK_LIBRARY};Threads::Threads")
  message(STATUS "osteon: OpenIGTLink ${OpenIGTLink_VERSION_MAJOR}.${OpenIGTLink_VERSION_MINOR} (protocol ${OpenIGTLink_PROTOCOL_VERSION}) at ${OSTEON_OPENIGTLINK_LIBRARY}")
endif()
