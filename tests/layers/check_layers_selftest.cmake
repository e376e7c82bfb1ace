# Shows that check_layers.cmake can fail: a tree whose lower layers include higher ones must be
# refused with each offending file:line, and the same tree without them must pass.
# Usage: cmake -DCHECKER=<check_layers.cmake> -DWORK=<scratch folder> -P check_layers_selftest.cmake
foreach(v CHECKER WORK)
  if(NOT DEFINED ${v})
    message(FATAL_ERROR "check_layers_selftest: give -D${v}=...")
  endif()
endforeach()

file(REMOVE_RECURSE "${WORK}")
file(WRITE "${WORK}/src/dem/core/good.h" "#pragma once\n#include <vector>\n#include \"dem/core/vec3.h\"\n")
file(WRITE "${WORK}/src/dem/world/good.h" "#pragma once\n#include \"dem/contact/good.h\"\n")
file(WRITE "${WORK}/src/dem/io/good.cpp" "#include \"dem/world/good.h\"\n")
file(WRITE "${WORK}/src/scene/good.cpp" "#include \"scene/good.h\"\n#include \"dem/core/good.h\"\n#include <toml++/toml.h>\n")
file(WRITE "${WORK}/src/vpp/damper/good.cpp" "#include \"vpp/damper/good.h\"\n#include \"vpp/settings/good.h\"\n#include \"vpp/analysis/good.h\"\n#include \"scene/good.h\"\n#include \"dem/core/good.h\"\n")
file(WRITE "${WORK}/src/vpp/calibration/good.cpp" "#include \"vpp/study/good.h\"\n#include \"vpp/damper/good.h\"\n")
file(WRITE "${WORK}/src/cli/main.cpp" "#include \"vpp/damper/good.h\"\n")

function(run_checker expect_ok label)
  execute_process(COMMAND "${CMAKE_COMMAND}" "-DROOT=${WORK}" -P "${CHECKER}"
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  set(all "${out}${err}")
  if(expect_ok AND NOT rc EQUAL 0)
    message(FATAL_ERROR "check_layers_selftest (${label}): a clean tree was refused:\n${all}")
  endif()
  if(NOT expect_ok AND rc EQUAL 0)
    message(FATAL_ERROR "check_layers_selftest (${label}): a tree with bad includes passed:\n${all}")
  endif()
  set(checker_output "${all}" PARENT_SCOPE)
endfunction()

run_checker(TRUE "clean tree")

# Each bad include at a known line; the checker must name every one.
file(WRITE "${WORK}/src/dem/core/bad.h" "#pragma once\n// a core header that knows the damper\n#include \"vpp/settings/config.h\"\n")
file(WRITE "${WORK}/src/dem/io/bad2.cpp" "#include \"dem/io/csv.h\"\n  #  include <scene/config.h>\n")
file(WRITE "${WORK}/src/scene/bad.cpp" "#include \"scene/good.h\"\n#include \"vpp/damper/damper.h\"\n")
file(WRITE "${WORK}/src/vpp/study/bad.cpp" "#include \"vpp/damper/good.h\"\n\n\n#include \"cli/main.h\"\n")
file(WRITE "${WORK}/src/vpp/study/bad_relative.cpp" "#include \"damper.h\"\n")
# Inside vpp: a room that includes a higher one, two rooms of one rank, a room without a rank, a
# file outside the rooms, an include that names no room.
file(WRITE "${WORK}/src/vpp/membrane/bad8.h" "#pragma once\n#include \"vpp/membrane/good.h\"\n#include \"vpp/settings/config.h\"\n")
file(WRITE "${WORK}/src/vpp/device/bad9.cpp" "#include \"vpp/damper/damper.h\"\n")
file(WRITE "${WORK}/src/vpp/extra/bad10.h" "#pragma once\n#include \"vpp/analysis/stats.h\"\n")
file(WRITE "${WORK}/src/vpp/loose.cpp" "#include <vector>\n")
file(WRITE "${WORK}/src/dem/loose.h" "#pragma once\n#include \"dem/core/vec3.h\"\n")
file(WRITE "${WORK}/src/vpp/analysis/bad11.cpp" "#include <vector>\n#include \"vpp/config.h\"\n")
file(WRITE "${WORK}/src/dem/contact/bad3.h" "#pragma once\n#include \"dem/world/world.h\"\n")
file(WRITE "${WORK}/src/dem/world/bad4.cpp" "#include \"dem/world/good.h\"\n#include \"dem/io/checkpoint.h\"\n")
# Inside dem: the kernels' folder under the contacts (a loop with contact -> kernels), two folders
# of one rank, a folder without a rank.
file(WRITE "${WORK}/src/dem/contact/bad5.h" "#pragma once\n#include \"dem/core/vec3.h\"\n#include \"dem/kernels/kernels.h\"\n")
file(WRITE "${WORK}/src/dem/bonds/bad6.h" "#pragma once\n#include \"dem/walls/wall.h\"\n")
file(WRITE "${WORK}/src/dem/extra/bad7.h" "#pragma once\n#include \"dem/core/vec3.h\"\n")
run_checker(FALSE "bad tree")
foreach(expected
    "src/dem/core/bad.h:3:" "src/dem/io/bad2.cpp:2:" "src/scene/bad.cpp:2:" "src/vpp/study/bad.cpp:4:"
    "src/vpp/study/bad_relative.cpp:1:" "src/dem/contact/bad3.h:2:" "src/dem/world/bad4.cpp:2:"
    "src/dem/contact/bad5.h:3:" "src/dem/bonds/bad6.h:2:" "src/dem/extra/bad7.h:2:"
    "src/vpp/membrane/bad8.h:3:" "src/vpp/device/bad9.cpp:1:" "src/vpp/extra/bad10.h:2:"
    "src/vpp/loose.cpp:1:" "src/vpp/analysis/bad11.cpp:2:" "src/dem/loose.h:1:")
  string(FIND "${checker_output}" "${expected}" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "check_layers_selftest: the refusal does not name ${expected}:\n${checker_output}")
  endif()
endforeach()
string(FIND "${checker_output}" "good" at)
if(NOT at EQUAL -1)
  message(FATAL_ERROR "check_layers_selftest: the refusal names a good file:\n${checker_output}")
endif()

file(REMOVE_RECURSE "${WORK}")
message(STATUS "check_layers_selftest: bad includes refused with file:line, a clean tree passes")
