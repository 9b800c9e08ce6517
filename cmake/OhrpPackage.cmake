# cpack -G DEB (in build/): a Debian package of what cmake --install puts (cmake/OhrpInstall.cmake),
# installed under /usr. Its Depends come from dpkg-shlibdeps (the Debian packages of the shared
# libraries the programs link: libmujoco2.2.2, libfcl0.7, libyaml-cpp0.7, libosmesa6, ...) plus
# what the programs start or serve; Recommends: the -dev packages find_package(ohrp) needs
# (cmake/ohrpConfig.cmake.in) and the plot scripts' Python modules.
set(CPACK_PACKAGE_NAME ohrp)
set(CPACK_PACKAGE_VENDOR "ohrp")
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY
    "OpenHRP-style humanoid platform on MuJoCo: simulator, shared-memory bridge, controllers")
set(CPACK_PACKAGE_CONTACT "ohrp maintainers")
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_STRIP_FILES ON)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_DEPENDS "python3, libjs-three, libjs-chart.js")
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS
    "cmake, g++, libmujoco-dev, libeigen3-dev, libfcl-dev, libyaml-cpp-dev, libcli11-dev, libboost-dev, python3-numpy, python3-matplotlib, ffmpeg")
if(TARGET ohrp_planning)  # exported ohrp::planning links OMPL (issue 34)
  string(APPEND CPACK_DEBIAN_PACKAGE_RECOMMENDS ", libompl-dev")
endif()
include(CPack)
