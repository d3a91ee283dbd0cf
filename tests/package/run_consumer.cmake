# Installs the lidarseg build tree into a scratch prefix, then configures, builds and runs a
# separate project that uses it through find_package(lidarseg): the segmentation of a
# synthetic corner, and the README's SegmentAlignment example, which fails unless it agrees
# with mrpt::slam::CICP on two scans of RAWLOG (MRPT's Telecom Faculty log), loading its
# options from OPTIONS (an INI file).
cmake_minimum_required(VERSION 3.16)
foreach(var LIDARSEG_BUILD_DIR CONSUMER_SOURCE_DIR WORK_DIR RAWLOG OPTIONS)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "run_consumer.cmake: ${var} is not set")
  endif()
endforeach()

file(REMOVE_RECURSE "${WORK_DIR}")
set(prefix "${WORK_DIR}/prefix")

function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "command failed (${rc}): ${ARGN}\n${out}\n${err}")
  endif()
  set(last_output "${out}" PARENT_SCOPE)
endfunction()

set(config_args "")
if(CONFIG)
  set(config_args --config ${CONFIG})
endif()
run(${CMAKE_COMMAND} --install "${LIDARSEG_BUILD_DIR}" --prefix "${prefix}" ${config_args})
run(${CMAKE_COMMAND} -S "${CONSUMER_SOURCE_DIR}" -B "${WORK_DIR}/build"
    -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_BUILD_TYPE=Release
    "-DCMAKE_CXX_FLAGS=${CONSUMER_CXX_FLAGS}" "-DCMAKE_EXE_LINKER_FLAGS=${CONSUMER_CXX_FLAGS}")
run(${CMAKE_COMMAND} --build "${WORK_DIR}/build")
run("${WORK_DIR}/build/lidarseg_consumer_corner")
message(STATUS "corner consumer says: ${last_output}")
if(NOT last_output MATCHES "corner: 2 segments")
  message(FATAL_ERROR "unexpected corner consumer output: ${last_output}")
endif()

if(NOT EXISTS "${RAWLOG}")
  message(FATAL_ERROR "missing ${RAWLOG} (Debian package mrpt-common; ./run.sh deps)")
endif()
# run() fails on the non-zero exit of a disagreement, printing both results.
run("${WORK_DIR}/build/lidarseg_consumer" "${RAWLOG}" "${OPTIONS}")
message(STATUS "alignment consumer says:\n${last_output}")
if(NOT last_output MATCHES "SegmentAlignment .*CICP .*difference ")
  message(FATAL_ERROR "unexpected alignment consumer output: ${last_output}")
endif()

# The README's tracking example over the whole log (fails on a lost scan, a non-finite pose,
# or a path length 10 % from the wheel odometry's).
run("${WORK_DIR}/build/lidarseg_consumer_track" "${RAWLOG}")
message(STATUS "tracking consumer says: ${last_output}")
if(NOT last_output MATCHES "tracked [0-9]+ scans, 0 lost")
  message(FATAL_ERROR "unexpected tracking consumer output: ${last_output}")
endif()

# The pure core through pkg-config, with no CMake on the consumer's side.
find_program(PKG_CONFIG pkg-config REQUIRED)
file(GLOB pc_file "${prefix}/lib*/pkgconfig/lidarseg-core.pc" "${prefix}/lib/*/pkgconfig/lidarseg-core.pc")
if(NOT pc_file)
  message(FATAL_ERROR "the install has no lidarseg-core.pc")
endif()
get_filename_component(pc_dir "${pc_file}" DIRECTORY)
set(ENV{PKG_CONFIG_PATH} "${pc_dir}")
run(${PKG_CONFIG} --cflags --libs lidarseg-core)
string(STRIP "${last_output}" pc_flags)
separate_arguments(pc_flags UNIX_COMMAND "${pc_flags}")
separate_arguments(consumer_flags UNIX_COMMAND "${CONSUMER_CXX_FLAGS}")
find_program(CXX NAMES c++ g++ REQUIRED)
run(${CXX} ${consumer_flags} "${CONSUMER_SOURCE_DIR}/core_only.cpp" -o "${WORK_DIR}/core_only" ${pc_flags}
    "-Wl,-rpath,${prefix}/lib")
run("${WORK_DIR}/core_only")
message(STATUS "pkg-config consumer says: ${last_output}")
if(NOT last_output MATCHES "core corner: 2 segments")
  message(FATAL_ERROR "unexpected pkg-config consumer output: ${last_output}")
endif()
