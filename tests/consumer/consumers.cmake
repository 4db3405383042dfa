# Shared by the consumer tests (run_consumer_test.cmake, tests/install/run_deb_test.cmake):
# builds and runs the consumer programs (tests/consumer: main.cpp, api_queries.cpp) against
# an installed cmkit, once through find_package (CMAKE_PREFIX_PATH = prefix) and once with
# the flags of `pkg-config --cflags --libs cmkit` (PKG_CONFIG_PATH = pcdir).
function(cmkit_run_checked what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${what} failed (${rc}):\n${out}\n${err}")
  endif()
endfunction()

function(cmkit_build_consumers source prefix pcdir work cxx)
  cmkit_run_checked("configuring the find_package consumer"
    ${CMAKE_COMMAND} -S ${source} -B ${work}/build -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_BUILD_TYPE=Release)
  cmkit_run_checked("building the find_package consumer" ${CMAKE_COMMAND} --build ${work}/build)
  cmkit_run_checked("the find_package consumer" ${work}/build/consumer)
  cmkit_run_checked("the find_package API consumer" ${work}/build/consumer_api)
  find_program(PKG_CONFIG pkg-config REQUIRED)
  execute_process(COMMAND ${CMAKE_COMMAND} -E env PKG_CONFIG_PATH=${pcdir} ${PKG_CONFIG} --cflags --libs cmkit
                  OUTPUT_VARIABLE flags OUTPUT_STRIP_TRAILING_WHITESPACE RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "pkg-config --cflags --libs cmkit failed (${rc}) with PKG_CONFIG_PATH=${pcdir}")
  endif()
  message(STATUS "pkg-config --cflags --libs cmkit: ${flags}")
  separate_arguments(flags UNIX_COMMAND "${flags}")
  cmkit_run_checked("building the pkg-config consumer"
    ${cxx} -std=c++20 ${source}/main.cpp ${flags} -o ${work}/consumer_pc)
  cmkit_run_checked("the pkg-config consumer" ${work}/consumer_pc)
  cmkit_run_checked("building the pkg-config API consumer"
    ${cxx} -std=c++20 ${source}/api_queries.cpp ${flags} -o ${work}/consumer_api_pc)
  cmkit_run_checked("the pkg-config API consumer" ${work}/consumer_api_pc)
  # The C API (include/cmkit/cmkit.h) from C11 with warnings as errors,
  # linked through `pkg-config --static` (the C++ runtime and the static
  # library's dependencies come from cmkit.pc): examples/c/drop_box.c.
  find_program(CC NAMES cc gcc)
  if(CC)
    execute_process(COMMAND ${CMAKE_COMMAND} -E env PKG_CONFIG_PATH=${pcdir} ${PKG_CONFIG} --static --cflags --libs cmkit
                    OUTPUT_VARIABLE cflags OUTPUT_STRIP_TRAILING_WHITESPACE RESULT_VARIABLE rc)
    if(NOT rc EQUAL 0)
      message(FATAL_ERROR "pkg-config --static --cflags --libs cmkit failed (${rc})")
    endif()
    separate_arguments(cflags UNIX_COMMAND "${cflags}")
    cmkit_run_checked("building the C consumer (C11, -Wall -Wextra -Wpedantic -Werror)"
      ${CC} -std=c11 -Wall -Wextra -Wpedantic -Werror ${source}/../../examples/c/drop_box.c
      ${cflags} -o ${work}/consumer_c)
    execute_process(COMMAND ${work}/consumer_c ${source}/../data/maps/two_halls.map RESULT_VARIABLE rc
                    OUTPUT_VARIABLE out ERROR_VARIABLE err)
    if(NOT rc EQUAL 0 OR NOT out MATCHES "dropped: fraction 0\\.39750.*closed door: fraction 0\\.449375.*entity door1")
      message(FATAL_ERROR "the C consumer failed (${rc}):\n${out}\n${err}")
    endif()
    message(STATUS "C consumer:\n${out}")
  endif()
endfunction()
