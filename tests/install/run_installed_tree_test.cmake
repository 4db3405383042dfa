# The installed tree stands alone: installs the build in CMKIT_BUILD_DIR into
# WORK_DIR/prefix, moves that tree to WORK_DIR/moved (so no path of the build
# or of the first prefix can be used), then, from another working directory,
# runs the moved cmkit's demo (which must find the installed bundled map) and
# info on the installed map, and checks the docs and licence are there and
# that no installed binary names the source or build tree.
file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR}/elsewhere)
execute_process(COMMAND ${CMAKE_COMMAND} --install ${CMKIT_BUILD_DIR} --prefix ${WORK_DIR}/prefix
                RESULT_VARIABLE rc OUTPUT_QUIET)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "cmake --install failed: ${rc}")
endif()
# Nothing may land outside the prefix (an absolute DESTINATION would).
file(STRINGS ${CMKIT_BUILD_DIR}/install_manifest.txt installed)
foreach(f IN LISTS installed)
  string(FIND "${f}" "${WORK_DIR}/prefix/" at)
  if(NOT at EQUAL 0)
    message(FATAL_ERROR "cmake --install --prefix put ${f} outside the prefix")
  endif()
endforeach()
# No installed program or library names the source or the build tree
# (builds are reproducible: CMakeLists.txt's prefix maps, data_paths.h). The
# prefix itself lies inside the build tree here, so the text files that name
# their prefix (cmkit.pc, the CMake package) are not searched: every file that
# is not text is.
find_program(GREP grep REQUIRED)
foreach(f IN LISTS installed)
  execute_process(COMMAND ${GREP} -Iq . ${f} RESULT_VARIABLE is_text)
  if(is_text EQUAL 0)
    continue()
  endif()
  foreach(tree ${CMKIT_SOURCE_DIR} ${CMKIT_BUILD_DIR})
    execute_process(COMMAND ${GREP} -c -a -F ${tree} ${f} OUTPUT_VARIABLE hits OUTPUT_STRIP_TRAILING_WHITESPACE)
    if(hits GREATER 0)
      message(FATAL_ERROR "the installed ${f} names ${tree} (${hits} lines)")
    endif()
  endforeach()
endforeach()
file(RENAME ${WORK_DIR}/prefix ${WORK_DIR}/moved)
set(root ${WORK_DIR}/moved)
foreach(f bin/cmkit share/cmkit/maps/lt4/lt4.map share/doc/cmkit/LICENSE share/doc/cmkit/README.md
          share/doc/cmkit/docs/fidelity.md include/cmkit/version.h)
  if(NOT EXISTS ${root}/${f})
    message(FATAL_ERROR "the installed tree has no ${f}")
  endif()
endforeach()
execute_process(COMMAND ${root}/bin/cmkit demo -o demo.png WORKING_DIRECTORY ${WORK_DIR}/elsewhere
                OUTPUT_VARIABLE out ERROR_VARIABLE err RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the installed cmkit demo failed (${rc}):\n${out}\n${err}")
endif()
string(FIND "${out}" "compiling ${root}/share/cmkit/maps/lt4/lt4.map" at)
if(at EQUAL -1)
  message(FATAL_ERROR "the installed demo did not use the installed map:\n${out}")
endif()
if(NOT EXISTS ${WORK_DIR}/elsewhere/demo.png)
  message(FATAL_ERROR "the installed demo wrote no picture")
endif()
execute_process(COMMAND ${root}/bin/cmkit info ${root}/share/cmkit/maps/lt4/lt4.map --quiet
                WORKING_DIRECTORY ${WORK_DIR}/elsewhere OUTPUT_VARIABLE out RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the installed cmkit info failed (${rc}):\n${out}")
endif()
message(STATUS "installed tree OK:\n${out}")
