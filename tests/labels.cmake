# Test labels on two axes (included by tests/CMakeLists.txt):
#
# what is tested (the area): format, model, loop, config, cli, daemon, modbus, can, linuxcnc, nc,
#   calibration, metrology, report, package, fuzz;
# what kind of test it is:
#   unit     in process: a test executable alone, with loopback sockets, pseudo-terminals and
#            temporary files at most. Seconds for all of them: `ctest -L unit`.
#   process  volcomp's own programs (volcompd, volcomp-sim, volcomp) run as processes.
#   system   a peer we did not write takes part: LinuxCNC, its rs274 interpreter, a QEMU guest
#            with SocketCAN, headless Chromium, mbpoll, cyclictest, dpkg and systemd-analyze.
#
#   fuzzing  a fuzz target fuzzing for a bounded time (the sanitizer pass only).
#
# scripts/test.sh says which kinds run in which pass, and why.

# Labels AREA and KIND on every test gtest_discover_tests finds in TARGET; extra arguments are
# gtest_discover_tests' own (PROPERTIES, DISCOVERY_TIMEOUT...). gtest_discover_tests writes its
# PROPERTIES unquoted into the generated file, so a list of two labels would arrive as two
# arguments: the labels are set by a file CTest includes after the discovered tests, on the
# names they were listed under.
function(volcomp_discover_tests target)
  set(VOLCOMP_TEST_KINDS unit process system)
  cmake_parse_arguments(T "" "AREA;KIND" "" ${ARGN})
  if(NOT T_AREA OR NOT T_KIND IN_LIST VOLCOMP_TEST_KINDS)
    message(FATAL_ERROR "volcomp_discover_tests(${target}): AREA and KIND (${VOLCOMP_TEST_KINDS})")
  endif()
  gtest_discover_tests(${target} TEST_LIST ${target}_TESTS ${T_UNPARSED_ARGUMENTS})
  set(labels_file ${CMAKE_CURRENT_BINARY_DIR}/${target}_labels.cmake)
  file(WRITE ${labels_file}
       "if(${target}_TESTS)\n"
       "  set_tests_properties(\${${target}_TESTS} PROPERTIES LABELS \"${T_AREA};${T_KIND}\")\n"
       "endif()\n")
  set_property(DIRECTORY APPEND PROPERTY TEST_INCLUDE_FILES ${labels_file})
endfunction()

# Labels AREA and KIND on the tests NAMES... added with add_test.
function(volcomp_test_labels)
  set(VOLCOMP_TEST_KINDS unit process system fuzzing)
  cmake_parse_arguments(T "" "AREA;KIND" "NAMES" ${ARGN})
  if(NOT T_AREA OR NOT T_KIND IN_LIST VOLCOMP_TEST_KINDS OR NOT T_NAMES)
    message(FATAL_ERROR "volcomp_test_labels: NAMES, AREA and KIND (${VOLCOMP_TEST_KINDS})")
  endif()
  set_tests_properties(${T_NAMES} PROPERTIES LABELS "${T_AREA};${T_KIND}")
endfunction()
