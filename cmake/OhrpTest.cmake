# ohrp_add_test(NAME name SOURCES a.cc b.cc LIBS lib... [LABELS l...] [TIMEOUT s] [SERIAL])
# Declares one GoogleTest executable, linked with the tests' shared helpers (tests/common:
# child processes, scratch files), and registers its tests with ctest. SERIAL: its tests run
# alone (real-time tests whose deadlines a parallel test would make them miss). Its timeout is
# tripled in the sanitizer build (OHRP_SANITIZE).
function(ohrp_add_test)
  cmake_parse_arguments(T "SERIAL" "NAME;TIMEOUT" "SOURCES;LIBS;LABELS" ${ARGN})
  if(NOT T_TIMEOUT)
    set(T_TIMEOUT 120)
  endif()
  # the sanitizer build runs two to three times slower
  if(OHRP_SANITIZE)
    math(EXPR T_TIMEOUT "${T_TIMEOUT} * 3")
  endif()
  if(NOT T_LABELS)
    set(T_LABELS unit)
  endif()
  add_executable(${T_NAME} ${T_SOURCES})
  target_link_libraries(${T_NAME} PRIVATE ${T_LIBS} ohrp::test_process GTest::gtest GTest::gtest_main
                        Threads::Threads)
  target_compile_definitions(${T_NAME} PRIVATE
    OHRP_SOURCE_DIR="${OHRP_SOURCE_DIR}"
    OHRP_BIN_DIR="${CMAKE_RUNTIME_OUTPUT_DIRECTORY}")
  set_target_properties(${T_NAME} PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR}/tests)
  set(serial FALSE)
  if(T_SERIAL)
    set(serial TRUE)
  endif()
  gtest_discover_tests(${T_NAME}
    DISCOVERY_TIMEOUT 60
    PROPERTIES LABELS "${T_LABELS}" TIMEOUT ${T_TIMEOUT} RUN_SERIAL ${serial})
endfunction()
