# The Debian package: runs cpack -G DEB in CMKIT_BUILD_DIR, unpacks the .deb
# into WORK_DIR/root with dpkg-deb -x, checks its control fields, and builds
# the find_package and pkg-config consumers (tests/consumer) against the
# unpacked /usr, then runs the unpacked cmkit.
include(${CMAKE_CURRENT_LIST_DIR}/../consumer/consumers.cmake)
file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR})
execute_process(COMMAND cpack -G DEB -B ${WORK_DIR}/out --config ${CMKIT_BUILD_DIR}/CPackConfig.cmake
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "cpack -G DEB failed (${rc}):\n${out}\n${err}")
endif()
file(GLOB debs ${WORK_DIR}/out/*.deb)
list(LENGTH debs n)
if(NOT n EQUAL 1)
  message(FATAL_ERROR "expected one .deb, found: ${debs}")
endif()
execute_process(COMMAND dpkg-deb --field ${debs} Package Version Depends OUTPUT_VARIABLE fields RESULT_VARIABLE rc)
if(NOT rc EQUAL 0 OR NOT fields MATCHES "Package: cmkit" OR NOT fields MATCHES "Depends: .*libc6")
  message(FATAL_ERROR "unexpected control fields of ${debs}:\n${fields}")
endif()
message(STATUS "${debs}:\n${fields}")
execute_process(COMMAND dpkg-deb -x ${debs} ${WORK_DIR}/root RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "dpkg-deb -x failed: ${rc}")
endif()
set(usr ${WORK_DIR}/root/usr)
execute_process(COMMAND ${usr}/bin/cmkit info ${usr}/share/cmkit/maps/lt4/lt4.map --quiet
                OUTPUT_VARIABLE out RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the packaged cmkit failed (${rc}):\n${out}")
endif()
# find_package and pkg-config against the unpacked package (cmkit.pc is relocatable).
file(GLOB_RECURSE pcs ${usr}/cmkit.pc)
list(GET pcs 0 pc)
get_filename_component(pcdir ${pc} DIRECTORY)
cmkit_build_consumers(${CONSUMER_SOURCE_DIR} ${usr} ${pcdir} ${WORK_DIR}/consumer ${CXX})
