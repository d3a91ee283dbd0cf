# Fails unless the code block that follows the line "<!-- snippet: PATH -->" in README is
# byte for byte the file PATH (relative to SOURCE_DIR): the README's example is the program
# the find_package consumer test compiles and runs.
#   cmake -DSOURCE_DIR=<lidarseg source> -DSNIPPET=<path in the tree> -DWORK_DIR=<scratch>
#         -P check_readme_snippet.cmake
cmake_minimum_required(VERSION 3.16)
foreach(var SOURCE_DIR SNIPPET WORK_DIR)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "check_readme_snippet.cmake: ${var} is not set")
  endif()
endforeach()

set(readme "${SOURCE_DIR}/README.md")
file(READ "${readme}" text)
file(READ "${SOURCE_DIR}/${SNIPPET}" expected)

set(marker "<!-- snippet: ${SNIPPET} -->\n")
string(FIND "${text}" "${marker}" at)
if(at EQUAL -1)
  message(FATAL_ERROR "${readme}: no line '<!-- snippet: ${SNIPPET} -->'")
endif()
string(LENGTH "${marker}" marker_length)
math(EXPR at "${at} + ${marker_length}")
string(SUBSTRING "${text}" ${at} -1 text)
# The fence must follow the marker directly; the block ends at the next fence line.
set(fence_open "```cpp\n")
string(FIND "${text}" "${fence_open}" open)
if(NOT open EQUAL 0)
  message(FATAL_ERROR "${readme}: the line after the snippet marker must be '```cpp'")
endif()
string(LENGTH "${fence_open}" open_length)
string(SUBSTRING "${text}" ${open_length} -1 text)
string(FIND "${text}" "\n```\n" close)
if(close EQUAL -1)
  message(FATAL_ERROR "${readme}: the snippet's code block is not closed")
endif()
math(EXPR close "${close} + 1")  # keep the code's last newline
string(SUBSTRING "${text}" 0 ${close} snippet)

if(NOT snippet STREQUAL expected)
  file(MAKE_DIRECTORY "${WORK_DIR}")
  set(extracted "${WORK_DIR}/readme_snippet.cpp")
  file(WRITE "${extracted}" "${snippet}")
  find_program(DIFF diff)
  if(DIFF)
    execute_process(COMMAND ${DIFF} -u "${SOURCE_DIR}/${SNIPPET}" "${extracted}" OUTPUT_VARIABLE delta)
  endif()
  message(FATAL_ERROR "README.md's snippet differs from ${SNIPPET} (keep them identical):\n${delta}")
endif()
message(STATUS "README.md's snippet is ${SNIPPET}")
