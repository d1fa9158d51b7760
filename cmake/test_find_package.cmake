# Installs the build into a scratch prefix, configures and builds tests/find_package against it
# with find_package(voxlux), and runs the consumer on the bundled cloud. Fails on any step.
# cmake -DBUILD=<build dir> -DSOURCE=<source dir> -DWORK=<scratch dir> -P test_find_package.cmake
file(REMOVE_RECURSE ${WORK})
function(step)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
  message("${out}")
  if(NOT code EQUAL 0)
    message(FATAL_ERROR "failed (${code}): ${ARGN}\n${err}")
  endif()
endfunction()
step(${CMAKE_COMMAND} --install ${BUILD} --prefix ${WORK}/prefix)
step(${CMAKE_COMMAND} -S ${SOURCE}/tests/find_package -B ${WORK}/consumer -DCMAKE_PREFIX_PATH=${WORK}/prefix
     -DCMAKE_BUILD_TYPE=Release)
step(${CMAKE_COMMAND} --build ${WORK}/consumer)
step(${WORK}/consumer/consumer ${SOURCE}/grids/cloud.vdb)
