# The man page softbond.1, made by help2man from `softbond --help` and
# `--version`, with each command's own --help as a section of its own:
#   cmake -DPROGRAM=path/softbond -DOUTPUT=softbond.1 -DWORK=dir -P man_page.cmake
file(MAKE_DIRECTORY ${WORK})
set(include "[NAME]\nsoftbond \\- real-time soft bodies: run, view and film YAML scenes\n")
foreach(command run view film eval info tetra keys)
  execute_process(COMMAND ${PROGRAM} ${command} --help OUTPUT_VARIABLE text RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "softbond ${command} --help failed")
  endif()
  string(REPLACE "\\" "\\\\" text "${text}")
  string(REGEX REPLACE "\n([ ]*)-" "\n\\1\\\\-" text "${text}")
  string(TOUPPER "${command}" upper)
  string(APPEND include "[COMMAND ${upper}]\n.nf\n${text}.fi\n")
endforeach()
string(APPEND include "[FILES]\n.TP\nshare/softbond/scenes/\nthe example scenes (softbond run share/softbond/scenes/default.yaml)\n"
  ".TP\nshare/doc/softbond/\nthe manual (docs/*.md), the examples, LICENSE and CHANGELOG.md\n"
  "[ENVIRONMENT]\n.TP\nSOFTBOND_THREADS\nthe solver's threads when neither --threads nor the scene's threads say\n"
  "[COPYRIGHT]\nMIT license: see LICENSE.\n"
  "[SEE ALSO]\nThe manual: docs/getting_started.md, docs/scene_keys.md (softbond keys), docs/library.md.\n")
file(WRITE ${WORK}/softbond.h2m "${include}")
execute_process(COMMAND help2man --no-info --section=1 --include=${WORK}/softbond.h2m
  "--name=real-time soft bodies: run, view and film YAML scenes" --output=${OUTPUT} ${PROGRAM}
  RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "help2man failed: ${err}")
endif()
