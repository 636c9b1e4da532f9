# SPDX-License-Identifier: GPL-3.0-or-later
# Registers the cases of a test script from the script's own list, so that no
# test name is kept by hand in CMake.
#
# sodt_add_script_cases(SCRIPT <script.sh> PREFIX <prefix>
#                       [ARGS <arg>...] [LABELS <label>...] [PROPERTIES <name> <value>...])
# `bash <script.sh> --list` prints one case a line: MODE NAME [LABEL,LABEL...].
# Each case becomes the test <prefix>.NAME, which runs
# `bash <script.sh> MODE <arg>...`, with the given LABELS, the line's own
# labels and the given (single-valued) PROPERTIES. The list is read when CMake
# configures, and editing the script configures again.
function(sodt_add_script_cases)
  cmake_parse_arguments(A "" "SCRIPT;PREFIX" "ARGS;LABELS;PROPERTIES" ${ARGN})
  execute_process(COMMAND bash "${A_SCRIPT}" --list
                  OUTPUT_VARIABLE listing ERROR_VARIABLE err RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0 OR NOT listing MATCHES "[a-z]")
    message(FATAL_ERROR "'bash ${A_SCRIPT} --list' gave no cases (exit ${rc}): ${err}")
  endif()
  set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS "${A_SCRIPT}")
  string(REPLACE "\n" ";" lines "${listing}")
  foreach(line IN LISTS lines)
    if(line STREQUAL "")
      continue()
    endif()
    if(NOT line MATCHES "^([a-z0-9-]+) +([a-z0-9_]+)( +([a-z0-9,]+))? *$")
      message(FATAL_ERROR "'bash ${A_SCRIPT} --list': cannot read the line '${line}'")
    endif()
    set(mode "${CMAKE_MATCH_1}")
    set(test "${A_PREFIX}.${CMAKE_MATCH_2}")
    string(REPLACE "," ";" labels "${CMAKE_MATCH_4}")
    add_test(NAME "${test}" COMMAND bash "${A_SCRIPT}" "${mode}" ${A_ARGS})
    if(A_PROPERTIES)
      set_tests_properties("${test}" PROPERTIES ${A_PROPERTIES})
    endif()
    set_property(TEST "${test}" APPEND PROPERTY LABELS ${A_LABELS} ${labels})
  endforeach()
endfunction()
