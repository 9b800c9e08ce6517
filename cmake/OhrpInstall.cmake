# cmake --install: the programs, the libraries a controller author links (exported as ohrp::*,
# found with find_package(ohrp)), their headers, the C library and header, a version header, the
# package configuration, and the data (cmake/OhrpData.cmake). Included at the end of the top-level
# CMakeLists, once every target exists. A new library for controller authors: add it to
# OHRP_EXPORTED_LIBRARIES (and its include folder to OHRP_PUBLIC_HEADER_DIRS).
include(CMakePackageConfigHelpers)

set(OHRP_CMAKE_INSTALL_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/ohrp)
set(OHRP_PLUGIN_INSTALL_DIR ${CMAKE_INSTALL_LIBDIR}/ohrp)

# every executable and plugin module of the program folders (not tests/), so that a new program
# is installed without a list to keep; the benchmarks (bench_*) stay in the build tree: they read
# the checkout
function(ohrp_collect_targets dir type out)
  get_property(targets DIRECTORY ${dir} PROPERTY BUILDSYSTEM_TARGETS)
  get_property(subdirs DIRECTORY ${dir} PROPERTY SUBDIRECTORIES)
  set(found "")
  foreach(t IN LISTS targets)
    get_target_property(t_type ${t} TYPE)
    if(t_type STREQUAL type AND NOT t MATCHES "^bench_")
      list(APPEND found ${t})
    endif()
  endforeach()
  foreach(sub IN LISTS subdirs)
    if(NOT sub MATCHES "/tests$")
      ohrp_collect_targets(${sub} ${type} sub_found)
      list(APPEND found ${sub_found})
    endif()
  endforeach()
  set(${out} ${found} PARENT_SCOPE)
endfunction()
ohrp_collect_targets(${CMAKE_SOURCE_DIR} EXECUTABLE OHRP_INSTALLED_PROGRAMS)
install(TARGETS ${OHRP_INSTALLED_PROGRAMS} RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR}
        COMPONENT programs)
# hw_driver's IO plugins (hw_driver --io <prefix>/lib/ohrp/libohrp_io_udp.so)
ohrp_collect_targets(${CMAKE_SOURCE_DIR} MODULE_LIBRARY OHRP_INSTALLED_PLUGINS)
install(TARGETS ${OHRP_INSTALLED_PLUGINS} LIBRARY DESTINATION ${OHRP_PLUGIN_INSTALL_DIR}
        COMPONENT programs)

# the libraries with their link dependencies (a static library exports its private ones too)
set(OHRP_EXPORTED_LIBRARIES
  ohrp_cli ohrp_shm_bridge ohrp_shm_c ohrp_datalog ohrp_vrml ohrp_robot_model ohrp_walking ohrp_collision
  ohrp_robot_io ohrp_controllers ohrp_balance ohrp_walk)
# the arm planner and the reach controller (issue 34), where the tree has them
foreach(lib ohrp_planning ohrp_reach)
  if(TARGET ${lib})
    list(APPEND OHRP_EXPORTED_LIBRARIES ${lib})
  endif()
endforeach()
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
  cli/include shm_bridge/include datalog/include robot_model/include robot_model/collision/include
  hw_driver/include controllers/include)
if(TARGET ohrp_planning)
  list(APPEND OHRP_PUBLIC_HEADER_DIRS robot_model/planning/include)
endif()
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
