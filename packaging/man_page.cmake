# Writes the gzipped man page OUTPUT of PROGRAM (run as `cmake -P`, see CMakeLists.txt): help2man
# reads `PROGRAM --help` and `--version`, adds the sections of INCLUDE and, for a program with
# subcommands (volcomp), a VERBS section with each verb's --help as printed.
cmake_minimum_required(VERSION 3.25)

get_filename_component(outdir "${OUTPUT}" DIRECTORY)
set(page "${outdir}/${NAME}.${SECTION}")
set(includes --include "${INCLUDE}")

execute_process(COMMAND "${PROGRAM}" --help OUTPUT_VARIABLE help RESULT_VARIABLE status)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "${PROGRAM} --help exited with ${status}")
endif()
# CLI11 lists subcommands under "Subcommands:", one per line, indented: "  eval   Evaluate...".
string(REGEX MATCH "\nSubcommands:\n(  [^\n]*\n)+" listing "${help}")
string(REGEX MATCHALL "\n  [a-z0-9-]+ " verbs "${listing}")
if(verbs)
  set(text "[VERBS]\n")
  foreach(verb IN LISTS verbs)
    string(STRIP "${verb}" verb)
    execute_process(COMMAND "${PROGRAM}" ${verb} --help OUTPUT_VARIABLE verbHelp
                    RESULT_VARIABLE status)
    if(NOT status EQUAL 0)
      message(FATAL_ERROR "${PROGRAM} ${verb} --help exited with ${status}")
    endif()
    # Shown as printed (no fill): backslashes escaped, a leading dot or quote made literal.
    string(REPLACE "\\" "\\e" verbHelp "${verbHelp}")
    string(REGEX REPLACE "(^|\n)([.'])" "\\1\\\\&\\2" verbHelp "${verbHelp}")
    string(APPEND text ".SS \"${NAME} ${verb}\"\n.nf\n${verbHelp}.fi\n")
  endforeach()
  file(WRITE "${outdir}/${NAME}-verbs.h2m" "${text}")
  list(APPEND includes --include "${outdir}/${NAME}-verbs.h2m")
endif()

execute_process(
  COMMAND "${HELP2MAN}" --locale=C.UTF-8 --no-info --no-discard-stderr --section=${SECTION} "--name=${DESCRIPTION}"
          ${includes} --output=${page} "${PROGRAM}"
  RESULT_VARIABLE status)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "help2man failed on ${PROGRAM}")
endif()
execute_process(COMMAND "${GZIP}" -9nf "${page}" RESULT_VARIABLE status)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "gzip failed on ${page}")
endif()
