# cmake --install: the programs, the libraries a controller author links (exported as ohrp::*,
# found with find_package(ohrp)), their headers, the C library and header, a version header, the
# package configuration, and the data (cmake/OhrpData.cmake). Included at the end of the top-level
# CMakeLists, once every target exists. A new library for controller authors: add it to
# OHRP_EXPORTED_LIBRARIES (and its include folder to OHRP_PUBLIC_HEADER_DIRS).
include(CMakePackageConfigHelpers)

set(OHRP_CMAKE_INSTALL_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/ohrp)
set(OHRP_PLUGIN_INSTALL_DIR ${CMAKE_INSTALL_LIBDIR}/ohrp)

# the programs of build/bin (the benchmarks stay in the build tree: they read the checkout)
set(OHRP_INSTALLED_PROGRAMS
  sim_host hw_driver hw_emulator
  ohrp_controllers_posture ohrp_controllers_track_ball ohrp_controllers_playback
  ohrp_controllers_balance ohrp_controllers_walk
  ohrp_run ohrp_sweep ohrp_push ohrp_identify ohrp_compare_logs ohrp_view ohrp_video
  ohrp_vrml2mjcf ohrp_selfcollision)
install(TARGETS ${OHRP_INSTALLED_PROGRAMS} RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR}
        COMPONENT programs)
# hw_driver's IO plugins (hw_driver --io <prefix>/lib/ohrp/libohrp_io_udp.so)
install(TARGETS ohrp_io_udp ohrp_io_replay LIBRARY DESTINATION ${OHRP_PLUGIN_INSTALL_DIR}
        COMPONENT programs)

# the libraries with their link dependencies (a static library exports its private ones too)
set(OHRP_EXPORTED_LIBRARIES
  ohrp_cli ohrp_shm_bridge ohrp_shm_c ohrp_vrml ohrp_robot_model ohrp_walking ohrp_collision
  ohrp_robot_io ohrp_controllers ohrp_balance ohrp_walk)
foreach(lib IN LISTS OHRP_EXPORTED_LIBRARIES)
  string(REGEX REPLACE "^ohrp_" "" export_name ${lib})
  set_target_properties(${lib} PROPERTIES EXPORT_NAME ${export_name})
endforeach()
install(TARGETS ${OHRP_EXPORTED_LIBRARIES} EXPORT ohrpTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT dev
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT programs NAMELINK_COMPONENT dev
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(EXPORT ohrpTargets NAMESPACE ohrp:: DESTINATION ${OHRP_CMAKE_INSTALL_DIR} COMPONENT dev)

# headers: each exported library's include/ folder, merged under <prefix>/include
set(OHRP_PUBLIC_HEADER_DIRS
  cli/include shm_bridge/include robot_model/include robot_model/collision/include
  hw_driver/include controllers/include)
foreach(dir IN LISTS OHRP_PUBLIC_HEADER_DIRS)
  install(DIRECTORY ${CMAKE_SOURCE_DIR}/${dir}/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
          COMPONENT dev)
endforeach()
install(FILES ${OHRP_GENERATED_INCLUDE_DIR}/ohrp/version.h
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/ohrp COMPONENT dev)

# ohrpConfig.cmake + ohrpConfigVersion.cmake (same major version: compatible)
configure_package_config_file(${CMAKE_SOURCE_DIR}/cmake/ohrpConfig.cmake.in
  ${CMAKE_BINARY_DIR}/cmake/ohrpConfig.cmake
  INSTALL_DESTINATION ${OHRP_CMAKE_INSTALL_DIR}
  PATH_VARS OHRP_DATA_INSTALL_DIR CMAKE_INSTALL_BINDIR)
write_basic_package_version_file(${CMAKE_BINARY_DIR}/cmake/ohrpConfigVersion.cmake
  VERSION ${PROJECT_VERSION} COMPATIBILITY SameMajorVersion)
install(FILES ${CMAKE_BINARY_DIR}/cmake/ohrpConfig.cmake
              ${CMAKE_BINARY_DIR}/cmake/ohrpConfigVersion.cmake
        DESTINATION ${OHRP_CMAKE_INSTALL_DIR} COMPONENT dev)
