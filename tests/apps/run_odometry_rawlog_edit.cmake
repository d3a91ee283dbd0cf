# Runs lidarseg-odometry with --write-rawlog on a rawlog, then checks that MRPT's
# rawlog-edit reads the result: the actions/sensory-frame layout with every scan.
execute_process(COMMAND ${ODOMETRY} -q --no-plots -n 200 --write-rawlog ${OUT}/with_lidarseg.rawlog ${INPUT}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "lidarseg-odometry failed: ${out} ${err}")
endif()
execute_process(COMMAND ${RAWLOG_EDIT} --info -i ${OUT}/with_lidarseg.rawlog
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message(STATUS "${out}")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "rawlog-edit failed (${rc}): ${err}")
endif()
foreach(pattern "Actions/SensoryFrame format +: Yes" "Overall number of objects +: 400" " / +200 /")
  if(NOT out MATCHES "${pattern}")
    message(FATAL_ERROR "rawlog-edit output lacks '${pattern}'")
  endif()
endforeach()
