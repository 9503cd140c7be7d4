# Fails when a file of volcomp::loop (LOOP_DIR) includes anything but a standard header, Eigen,
# volcomp/model or volcomp/loop: the loop depends on the model only (no JSON, Asio, logging or
# systemd). A compile test could not show this, since those headers sit in /usr/include too.
file(GLOB_RECURSE files ${LOOP_DIR}/*.hpp ${LOOP_DIR}/*.cpp)
if(NOT files)
  message(FATAL_ERROR "no sources under ${LOOP_DIR}")
endif()
set(bad "")
foreach(file IN LISTS files)
  file(STRINGS ${file} lines REGEX "^[ \t]*#[ \t]*include")
  foreach(line IN LISTS lines)
    string(REGEX REPLACE "^[ \t]*#[ \t]*include[ \t]*[<\"]([^>\"]+)[>\"].*$" "\\1" header "${line}")
    # Standard headers have no directory and no extension (<array>, <cmath>).
    if(header MATCHES "^[a-z_]+$" OR header MATCHES "^(Eigen/|volcomp/model/|volcomp/loop/)")
      continue()
    endif()
    list(APPEND bad "${file}: ${header}")
  endforeach()
endforeach()
if(bad)
  list(JOIN bad "\n  " text)
  message(FATAL_ERROR "volcomp::loop includes headers outside the standard library, Eigen, the "
                      "model and the loop:\n  ${text}")
endif()
list(LENGTH files count)
message(STATUS "volcomp::loop: ${count} files include only the standard library, Eigen, the model "
               "and the loop")
