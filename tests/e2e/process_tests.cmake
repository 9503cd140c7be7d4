# Whole-process tests: volcomp-sim and volcompd as processes, ports/ptys chosen at run time,
# synchronised on pipes, log files, sd_notify datagrams and process exit (label modbus).
# Included from tests/e2e/CMakeLists.txt.
add_executable(volcomp_e2e_process_tests
  compensation_e2e_test.cpp
  safety_e2e_test.cpp
  timing_faults_e2e_test.cpp
  hostile_conditions_e2e_test.cpp
  latch_saturation_e2e_test.cpp
  lifecycle_e2e_test.cpp
  hostile_e2e_test.cpp
  commissioning_e2e_test.cpp
  latency_compensation_e2e_test.cpp)
target_link_libraries(volcomp_e2e_process_tests PRIVATE nlohmann_json::nlohmann_json
                      volcomp_testutil volcomp_warnings)
volcomp_test_paths(volcomp_e2e_process_tests VOLCOMP_SIM_PATH=target:volcomp-sim
                   VOLCOMPD_PATH=target:volcompd VOLCOMP_EXAMPLES_DIR=source:config/examples)
# Each case runs its own processes for a few seconds; RUN_SERIAL keeps timings honest on a
# 2-core machine (a starved daemon would look like a slow controller).
volcomp_discover_tests(volcomp_e2e_process_tests AREA modbus KIND process
  PROPERTIES TIMEOUT 60 RUN_SERIAL TRUE DISCOVERY_TIMEOUT 30)

# The Modbus server role: volcompd as a process driven by libmodbus' client and mbpoll over TCP
# and RTU (pseudo-terminals); label modbus.
add_executable(volcomp_e2e_server_tests modbus_server_e2e_test.cpp
  modbus_server_hostile_e2e_test.cpp)
target_link_libraries(volcomp_e2e_server_tests PRIVATE volcomp::daemon PkgConfig::MODBUS
                      nlohmann_json::nlohmann_json volcomp_testutil volcomp_warnings)
volcomp_test_paths(volcomp_e2e_server_tests VOLCOMP_SIM_PATH=target:volcomp-sim
                   VOLCOMPD_PATH=target:volcompd VOLCOMP_EXAMPLES_DIR=source:config/examples)
volcomp_discover_tests(volcomp_e2e_server_tests AREA modbus KIND process
  PROPERTIES TIMEOUT 60 RUN_SERIAL TRUE DISCOVERY_TIMEOUT 30)

# The 1 kHz comparison harness (bench/daemon/run_1khz.sh) in short: two blocks of 3 s each of the
# empty-loop baseline (cyclictest) and of volcompd at 1 kHz against volcomp-sim. No assertion on
# the missed-deadline counts (they are the machine's); the harness fails when a figure is missing
# or when a write in the simulator's record breaks the limiter. It pins both loops to one CPU,
# hence RUN_SERIAL.
find_program(CYCLICTEST cyclictest)
if(CYCLICTEST)
  add_test(NAME daemon_1khz_vs_baseline_smoke
           COMMAND env BLOCKS=2 BLOCK_S=3 VOLCOMPD=$<TARGET_FILE:volcompd>
                   VOLCOMP_SIM=$<TARGET_FILE:volcomp-sim>
                   ${PROJECT_SOURCE_DIR}/bench/daemon/run_1khz.sh)
  set_tests_properties(daemon_1khz_vs_baseline_smoke PROPERTIES
    TIMEOUT 60 RUN_SERIAL TRUE FAIL_REGULAR_EXPRESSION "run_1khz: FAILED")
  volcomp_test_labels(NAMES daemon_1khz_vs_baseline_smoke AREA daemon KIND system)
else()
  message(WARNING "cyclictest (Debian rt-tests) not found: the 1 kHz harness's smoke test is not run")
endif()
