# A committed page that is a command's output must be that output, byte for
# byte:  cmake -DCOMMAND="prog;args" -DFILE=docs/page.md -DREGENERATE="how" -P check_generated.cmake
execute_process(COMMAND ${COMMAND} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${COMMAND} failed (${rc}): ${err}")
endif()
file(READ ${FILE} committed)
if(NOT out STREQUAL committed)
  get_filename_component(name ${FILE} NAME)
  set(generated ${CMAKE_CURRENT_BINARY_DIR}/${name}.generated)
  file(WRITE ${generated} "${out}")
  execute_process(COMMAND diff -u ${FILE} ${generated} OUTPUT_VARIABLE difference)
  message("${difference}")
  message(FATAL_ERROR "${FILE} is not the output of the code (${generated}, the diff above); "
    "regenerate it: ${REGENERATE}")
endif()
