# lidarseg-inspect --report, then the page in headless Chromium: it must load without a
# script error, show the results table and load every image.
execute_process(COMMAND ${INSPECT} ${INPUT} --report ${OUT} --gallery 6 RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "lidarseg-inspect --report failed (${rc}): ${out} ${err}")
endif()
execute_process(
  COMMAND ${CHROMIUM} --headless --disable-gpu --no-sandbox --allow-file-access-from-files
          --enable-logging=stderr --v=0 --dump-dom file://${OUT}/index.html
  RESULT_VARIABLE rc OUTPUT_VARIABLE dom ERROR_VARIABLE log TIMEOUT 120)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "chromium failed (${rc}): ${log}")
endif()
if(NOT dom MATCHES "<table id=\"results\">")
  message(FATAL_ERROR "no results table in the page:\n${dom}")
endif()
if(NOT dom MATCHES "images loaded=([0-9]+) broken=0")
  string(REGEX MATCH "images[^<]*" check "${dom}")
  message(FATAL_ERROR "images did not all load: '${check}'")
endif()
set(loaded ${CMAKE_MATCH_1})
if(loaded LESS 9)
  message(FATAL_ERROR "only ${loaded} images loaded (3 plots and 6 frames expected)")
endif()
if(log MATCHES "Uncaught|CONSOLE.*[Ee]rror")
  message(FATAL_ERROR "the page logged an error:\n${log}")
endif()
message(STATUS "report loads in Chromium: ${loaded} images, table present")
