# Paths for tests without an absolute path in any compile command (included by
# tests/CMakeLists.txt and fuzz/CMakeLists.txt). An absolute path of the checkout in a definition
# would make every object that has it differ between two clones, so that a fresh clone in
# another folder (as CI makes) would find none of them in the compiler cache. Instead each
# definition is a call that finds the path at run time from the executable's own place in the
# build tree (tests/testutil/test_paths.hpp):
#
#   volcomp_test_paths(TARGET NAME=source:RELATIVE | NAME=build:RELATIVE | NAME=target:OTHER ...)
#
# source:RELATIVE is a file or folder of the source tree (e.g. config/examples), build:RELATIVE
# one of the build tree, target:OTHER the file another target builds (e.g. volcomp; TARGET then
# depends on it). Each NAME becomes a macro of TARGET's sources
# that gives a std::string.
function(volcomp_test_paths target)
  # Computed here, not at the file's scope: fuzz/ calls this too, from a directory that does not
  # see tests/' variables.
  file(RELATIVE_PATH source_from_build ${CMAKE_BINARY_DIR} ${PROJECT_SOURCE_DIR})
  if(source_from_build STREQUAL "")
    set(source_from_build .)
  endif()
  file(RELATIVE_PATH binary_dir ${CMAKE_BINARY_DIR} ${CMAKE_CURRENT_BINARY_DIR})
  if(binary_dir STREQUAL "")
    set(binary_dir .)
  endif()
  set(definitions VOLCOMP_TEST_BINARY_DIR="${binary_dir}"
                  VOLCOMP_TEST_SOURCE_FROM_BUILD="${source_from_build}")
  foreach(item IN LISTS ARGN)
    if(item MATCHES "^([A-Z0-9_]+)=source:(.*)$")
      list(APPEND definitions "${CMAKE_MATCH_1}=volcomp_test_source_path(\"${CMAKE_MATCH_2}\")")
    elseif(item MATCHES "^([A-Z0-9_]+)=build:(.*)$")
      list(APPEND definitions "${CMAKE_MATCH_1}=volcomp_test_build_path(\"${CMAKE_MATCH_2}\")")
    elseif(item MATCHES "^([A-Z0-9_]+)=target:(.*)$")
      set(file "$<PATH:RELATIVE_PATH,$<TARGET_FILE:${CMAKE_MATCH_2}>,${CMAKE_BINARY_DIR}>")
      list(APPEND definitions "${CMAKE_MATCH_1}=volcomp_test_build_path(\"${file}\")")
      add_dependencies(${target} ${CMAKE_MATCH_2})
    else()
      message(FATAL_ERROR "volcomp_test_paths(${target}): '${item}' is not NAME=source:PATH or "
                          "NAME=build:PATH or NAME=target:TARGET")
    endif()
  endforeach()
  target_compile_definitions(${target} PRIVATE ${definitions})
  target_compile_options(${target} PRIVATE
                         "SHELL:-include ${PROJECT_SOURCE_DIR}/tests/testutil/test_paths.hpp")
endfunction()
