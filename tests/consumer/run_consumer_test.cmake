# Installs the cmkit build in CMKIT_BUILD_DIR into WORK_DIR/prefix, then builds and runs the
# consumer program against it with find_package and with pkg-config (consumers.cmake).
include(${CMAKE_CURRENT_LIST_DIR}/consumers.cmake)
file(REMOVE_RECURSE ${WORK_DIR})
cmkit_run_checked("cmake --install" ${CMAKE_COMMAND} --install ${CMKIT_BUILD_DIR} --prefix ${WORK_DIR}/prefix)
cmkit_build_consumers(${CONSUMER_SOURCE_DIR} ${WORK_DIR}/prefix ${WORK_DIR}/prefix/${CMKIT_LIBDIR}/pkgconfig
                      ${WORK_DIR} ${CXX})
