# Fails when docs/config.md is not what the settings table (src/vpp/settings/settings.cpp) generates, so the
# reference cannot drift from the keys the reader accepts.
# Usage: cmake -DVPPDEM=<vppdem binary> -DDOC=<docs/config.md> -P check_config_doc.cmake
foreach(v VPPDEM DOC)
  if(NOT DEFINED ${v})
    message(FATAL_ERROR "check_config_doc: give -D${v}=...")
  endif()
endforeach()
execute_process(COMMAND "${VPPDEM}" config-reference RESULT_VARIABLE rc OUTPUT_VARIABLE generated ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "check_config_doc: '${VPPDEM} config-reference' failed (${rc}): ${err}")
endif()
if(NOT EXISTS "${DOC}")
  message(FATAL_ERROR "check_config_doc: ${DOC} is missing; generate it: build/vppdem config-reference > docs/config.md")
endif()
file(READ "${DOC}" written)
if(NOT written STREQUAL generated)
  message(FATAL_ERROR "check_config_doc: ${DOC} differs from the settings table (src/vpp/settings/settings.cpp); "
                      "regenerate it: build/vppdem config-reference > docs/config.md")
endif()
message(STATUS "check_config_doc: ${DOC} is the settings table's reference")
