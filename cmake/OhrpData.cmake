# The project's data as the programs find it (cli/include/cli/data_dir.h): <bin>/../share/ohrp.
#  - build tree: build/share/ohrp is a symbolic link to the checkout, so that build/bin/* and
#    build/tests/* read the checkout's files (and a scenario's "../shared/..." still resolves
#    beside the checkout, as before);
#  - installed: the folders below, copied to <prefix>/share/ohrp with their checkout-relative paths
#    (a scenario's "mjcf/hrp1s/scene_flat.xml" or "controllers/poses/x.yaml" resolves there too).
# Nothing else is compiled in: the installed programs find their data relative to themselves.

set(OHRP_DATA_INSTALL_DIR ${CMAKE_INSTALL_DATADIR}/ohrp)

file(MAKE_DIRECTORY ${CMAKE_BINARY_DIR}/share)
if(NOT EXISTS ${CMAKE_BINARY_DIR}/share/ohrp)
  file(CREATE_LINK ${CMAKE_SOURCE_DIR} ${CMAKE_BINARY_DIR}/share/ohrp SYMBOLIC)
endif()

# folders (trailing slash: their content) and single files, relative to the checkout
set(OHRP_DATA_FOLDERS mjcf scenarios controllers/poses tools/view/web tools/scripts)
set(OHRP_DATA_FILES tools/push/plot_push.py tools/sweep/plot_sweep.py)

foreach(folder IN LISTS OHRP_DATA_FOLDERS)
  get_filename_component(parent ${folder} DIRECTORY)
  install(DIRECTORY ${CMAKE_SOURCE_DIR}/${folder}
          DESTINATION ${OHRP_DATA_INSTALL_DIR}/${parent}
          COMPONENT data
          PATTERN "__pycache__" EXCLUDE PATTERN "*.pyc" EXCLUDE)
endforeach()
foreach(file IN LISTS OHRP_DATA_FILES)
  get_filename_component(parent ${file} DIRECTORY)
  install(PROGRAMS ${CMAKE_SOURCE_DIR}/${file} DESTINATION ${OHRP_DATA_INSTALL_DIR}/${parent}
          COMPONENT data)
endforeach()
