# Installs the build into a scratch prefix, then configures, builds and runs
# tests/consumer against it: the find_package(depthcull) path users take.
set(prefix ${BUILD_DIR}/consumer-check/prefix)
set(consumer_build ${BUILD_DIR}/consumer-check/build)
file(REMOVE_RECURSE ${BUILD_DIR}/consumer-check)
# CONSUMER_FLAGS: "|"-separated cache settings (the build's compilers, sanitizer link flags).
string(REPLACE "|" ";" consumer_flags "${CONSUMER_FLAGS}")
foreach(step
    "${CMAKE_COMMAND};--install;${BUILD_DIR};--prefix;${prefix}"
    "${CMAKE_COMMAND};-S;${SOURCE_DIR}/tests/consumer;-B;${consumer_build};-G;Ninja;-DCMAKE_PREFIX_PATH=${prefix};${consumer_flags}"
    "${CMAKE_COMMAND};--build;${consumer_build}"
    "${consumer_build}/consumer;${SOURCE_DIR}/examples/meadow.json"
    "${consumer_build}/consumer_c")
  execute_process(COMMAND ${step} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "consumer check failed at: ${step}\n${out}\n${err}")
  endif()
endforeach()
message(STATUS "consumer: ${out}")
