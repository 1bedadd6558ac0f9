# cmake -DSTRATA_BUILD_DIR=<a built Strata> -DCONSUMER_SOURCE_DIR=<tests/package> -DWORK_DIR=<scratch>
#       [-DCOMPONENTS=physics;navmesh;assets] -P RunConsumer.cmake
# Installs the build into WORK_DIR/prefix, configures and builds the consumer project against it (nothing
# but CMAKE_PREFIX_PATH points it there) and runs it. Any failing step fails the script.
foreach(variable STRATA_BUILD_DIR CONSUMER_SOURCE_DIR WORK_DIR)
  if(NOT DEFINED ${variable})
    message(FATAL_ERROR "RunConsumer.cmake needs -D${variable}=...")
  endif()
endforeach()
if(NOT DEFINED COMPONENTS)
  set(COMPONENTS physics navmesh assets)
endif()

function(run what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE result)
  if(NOT result EQUAL 0)
    message(FATAL_ERROR "${what} failed (${result})")
  endif()
endfunction()

# Commas: a list's semicolons would split the argument on its way through execute_process.
string(REPLACE ";" "," component_text "${COMPONENTS}")

file(REMOVE_RECURSE ${WORK_DIR})
set(prefix ${WORK_DIR}/prefix)
run("cmake --install" ${CMAKE_COMMAND} --install ${STRATA_BUILD_DIR} --prefix ${prefix})
run("configuring the consumer" ${CMAKE_COMMAND} -S ${CONSUMER_SOURCE_DIR} -B ${WORK_DIR}/build
    -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=${prefix} "-DSTRATA_CONSUMER_COMPONENTS=${component_text}")
run("building the consumer" ${CMAKE_COMMAND} --build ${WORK_DIR}/build)
run("the consumer" ${WORK_DIR}/build/strata_consumer)

# The installed CLI, run from another folder with no level named: it must find the installed sample level
# beside its prefix (share/strata/levels), not the source tree it was built from.
if(EXISTS ${prefix}/bin/strata)
  set(elsewhere ${WORK_DIR}/elsewhere)
  file(MAKE_DIRECTORY ${elsewhere})
  execute_process(COMMAND ${prefix}/bin/strata demo --steps 30 --crates 2 --agents 2 --no-player --out-dir out
                  WORKING_DIRECTORY ${elsewhere} RESULT_VARIABLE result OUTPUT_VARIABLE output ERROR_VARIABLE errors)
  if(NOT result EQUAL 0)
    message(FATAL_ERROR "the installed strata demo failed (${result}):\n${output}\n${errors}")
  endif()
  string(FIND "${output}" "level ${prefix}/share/strata/levels/courtyard.obj" found)
  if(found EQUAL -1)
    message(FATAL_ERROR "the installed strata demo did not use the installed level:\n${output}")
  endif()
  message(STATUS "installed strata demo ran from ${elsewhere} on ${prefix}/share/strata/levels/courtyard.obj")
endif()
