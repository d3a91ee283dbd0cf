# Simulates the whole maze run, then checks that MRPT's rawlog-edit reads the rawlog and
# finds the three sensors.
execute_process(COMMAND ${SIMULATE} -w ${WORLDS}/maze.world -t ${WORLDS}/maze.traj --seed 5 -o ${OUT}/maze
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "lidarseg-simulate failed: ${out} ${err}")
endif()
execute_process(COMMAND ${RAWLOG_EDIT} --info -i ${OUT}/maze.rawlog
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message(STATUS "${out}")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "rawlog-edit failed (${rc}): ${err}")
endif()
foreach(pattern "Observations format +: Yes" "CAMERA / +[0-9]+" "LIDAR / +5362 /50.000" "ODOMETRY / +5362")
  if(NOT out MATCHES "${pattern}")
    message(FATAL_ERROR "rawlog-edit output lacks '${pattern}'")
  endif()
endforeach()
