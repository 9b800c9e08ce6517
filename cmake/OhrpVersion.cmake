# The version header <ohrp/version.h> (project(ohrp VERSION ...) and the segment layout version,
# read from shm_bridge/layout.h's kLayoutVersion, which is also libohrp_shm_c's SOVERSION).
file(STRINGS ${CMAKE_SOURCE_DIR}/shm_bridge/include/shm_bridge/layout.h layout_line
     REGEX "inline constexpr uint32_t kLayoutVersion = [0-9]+")
string(REGEX MATCH "kLayoutVersion = ([0-9]+)" _ "${layout_line}")
set(OHRP_LAYOUT_VERSION "${CMAKE_MATCH_1}")
if(NOT OHRP_LAYOUT_VERSION)
  message(FATAL_ERROR "cannot read kLayoutVersion from shm_bridge/include/shm_bridge/layout.h")
endif()
set(OHRP_GENERATED_INCLUDE_DIR ${CMAKE_BINARY_DIR}/include)
configure_file(${CMAKE_SOURCE_DIR}/cmake/version.h.in ${OHRP_GENERATED_INCLUDE_DIR}/ohrp/version.h
               @ONLY)
