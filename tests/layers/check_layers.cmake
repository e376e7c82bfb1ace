# Checks that every layer of src/ includes only itself and the layers below it:
#   dem    (generic DEM core)             may include dem/
#   scene  (configs, generic scenes)      may include dem/, scene/
#   vpp    (the damper)                   may include dem/, scene/, vpp/
# cli/ (the command) and a Python module on top may include anything below them.
# Inside dem the folders are ranked; a folder includes itself and folders of a lower rank only,
# so no two folders include each other, directly or round a loop:
#   0  core                             vectors, lanes, particles, materials, threads, the shear spring, pressure
#   1  bonds, walls, mesh, clumps       each on the core alone
#   2  detect, integrate                the broad phase and pair geometry; the integrator and time step
#   3  contact                          the contact laws, the live contacts' stores, interaction lists
#   4  kernels                          the step's SIMD kernels and their shared bodies, the work split
#   5  world                            the World, its step, its contacts' lifecycle, the walls' state
#   6  io, batch                        file formats; the batch engine (systems packed from Worlds)
# A folder of src/dem that is not in this table is refused until it is given a rank here.
# Inside vpp the same, over its rooms (each room's README.md says what lives there):
#   0  analysis                         the records' columns, the loops' energies, statistics, plots
#   1  membrane                         the foil, the mesh membranes, the gas and the air in them
#   2  settings                         the config and the one table of its keys
#   3  foil_checks, damper, device      the applications: the foil's checks, the damper, devices
#   4  study                            sweeps of dampers and devices, their records, the key reference
#   5  calibration                      studies fitted to an experiment's loops
#   6  commands                         the commands' arguments turned into their runs' options, for both front doors
# Every file of src/dem and src/vpp lives in a folder (room): one directly in src/dem or src/vpp is refused.
# Usage: cmake -DROOT=<folder that holds src/> -P check_layers.cmake
# Fails naming each offending file:line; quoted includes must name their layer folder.
if(NOT DEFINED ROOT)
  message(FATAL_ERROR "check_layers: give -DROOT=<folder that holds src/>")
endif()
if(NOT IS_DIRECTORY "${ROOT}/src/dem")
  message(FATAL_ERROR "check_layers: '${ROOT}/src/dem' is not a folder")
endif()

set(known dem scene vpp cli python)
set(allowed_dem dem)
set(allowed_scene dem scene)
set(allowed_vpp dem scene vpp)

# The rank of a folder of src/dem ("" when it has none).
function(dem_rank folder out)
  set(r "")
  if(folder STREQUAL "core")
    set(r 0)
  elseif(folder MATCHES "^(bonds|walls|mesh|clumps)$")
    set(r 1)
  elseif(folder MATCHES "^(detect|integrate)$")
    set(r 2)
  elseif(folder STREQUAL "contact")
    set(r 3)
  elseif(folder STREQUAL "kernels")
    set(r 4)
  elseif(folder STREQUAL "world")
    set(r 5)
  elseif(folder MATCHES "^(io|batch)$")
    set(r 6)
  endif()
  set(${out} "${r}" PARENT_SCOPE)
endfunction()

# The rank of a room of src/vpp ("" when it has none).
function(vpp_rank folder out)
  set(r "")
  if(folder STREQUAL "analysis")
    set(r 0)
  elseif(folder STREQUAL "membrane")
    set(r 1)
  elseif(folder STREQUAL "settings")
    set(r 2)
  elseif(folder MATCHES "^(foil_checks|damper|device)$")
    set(r 3)
  elseif(folder STREQUAL "study")
    set(r 4)
  elseif(folder STREQUAL "calibration")
    set(r 5)
  elseif(folder STREQUAL "commands")
    set(r 6)
  endif()
  set(${out} "${r}" PARENT_SCOPE)
endfunction()

set(what_dem "a folder of src/dem")
set(what_vpp "a room of src/vpp")
set(order_dem "core <- bonds, walls, mesh, clumps <- detect, integrate <- contact <- kernels <- world <- io, batch")
set(order_vpp "analysis <- membrane <- settings <- foil_checks, damper, device <- study <- calibration <- commands")

set(bad "")
set(checked 0)
foreach(layer dem scene vpp)
  file(GLOB_RECURSE files LIST_DIRECTORIES false "${ROOT}/src/${layer}/*")
  list(SORT files)
  foreach(f IN LISTS files)
    if(NOT f MATCHES "\\.(h|hh|hpp|c|cc|cpp|cxx|inl)$")
      continue()
    endif()
    math(EXPR checked "${checked} + 1")
    file(READ "${f}" text)
    # One list element per line: characters CMake lists treat specially are masked first.
    string(REPLACE ";" "<semicolon>" text "${text}")
    string(REPLACE "[" "<open>" text "${text}")
    string(REPLACE "]" "<close>" text "${text}")
    string(REPLACE "\\" "<backslash>" text "${text}")
    string(REPLACE "\n" ";" lines "${text}")
    file(RELATIVE_PATH rel "${ROOT}" "${f}")
    # A file outside the ranked folders would escape the rank check below.
    if(layer MATCHES "^(dem|vpp)$" AND NOT rel MATCHES "^src/${layer}/[^/]+/")
      list(APPEND bad "${rel}:1: a file directly in src/${layer}: every file lives in ${what_${layer}} (${order_${layer}})")
    endif()
    set(n 0)
    foreach(line IN LISTS lines)
      math(EXPR n "${n} + 1")
      if(NOT line MATCHES "^[ \t]*#[ \t]*include[ \t]*([<\"])([^>\"]*)[>\"]")
        continue()
      endif()
      set(quote "${CMAKE_MATCH_1}")
      set(path "${CMAKE_MATCH_2}")
      string(REGEX REPLACE "/.*" "" top "${path}")
      if(NOT path MATCHES "/")
        set(top "")
      endif()
      list(FIND known "${top}" k)
      if(k EQUAL -1)
        if(quote STREQUAL "\"")
          list(APPEND bad "${rel}:${n}: #include \"${path}\": a project include names its layer folder (allowed here: ${allowed_${layer}})")
        endif()
        continue()  # a system or third-party header
      endif()
      # Inside dem and vpp: the folder (room) of the including file against the included one's.
      if(path MATCHES "^${layer}/([^/]+)/" AND rel MATCHES "^src/${layer}/([^/]+)/" AND layer MATCHES "^(dem|vpp)$")
        string(REGEX REPLACE "^src/${layer}/([^/]+)/.*" "\\1" from "${rel}")
        string(REGEX REPLACE "^${layer}/([^/]+)/.*" "\\1" to "${path}")
        cmake_language(CALL ${layer}_rank "${from}" rank_from)
        cmake_language(CALL ${layer}_rank "${to}" rank_to)
        if(rank_from STREQUAL "" OR rank_to STREQUAL "")
          list(APPEND bad "${rel}:${n}: ${layer}/${from} includes ${path}: ${what_${layer}} without a rank (give it one in tests/layers/check_layers.cmake)")
        elseif(NOT from STREQUAL to AND NOT rank_to LESS rank_from)
          list(APPEND bad "${rel}:${n}: ${layer}/${from} (rank ${rank_from}) includes ${path} (${layer}/${to}, rank ${rank_to}): a folder includes only itself and lower ranks (${order_${layer}})")
        endif()
      elseif(layer STREQUAL "vpp" AND path MATCHES "^vpp/[^/]+$")
        list(APPEND bad "${rel}:${n}: #include \"${path}\": src/vpp's files live in rooms (vpp/ROOM/file.h)")
      endif()
      list(FIND allowed_${layer} "${top}" a)
      if(a EQUAL -1)
        list(APPEND bad "${rel}:${n}: layer ${layer} includes ${path} of the higher layer ${top} (allowed here: ${allowed_${layer}})")
      endif()
    endforeach()
  endforeach()
endforeach()

if(bad)
  list(LENGTH bad nbad)
  string(REPLACE ";" "\n  " report "${bad}")
  message(FATAL_ERROR "check_layers: ${nbad} include(s) against the layers (dem <- scene <- vpp <- cli, python):\n  ${report}")
endif()
message(STATUS "check_layers: ${checked} files of src/dem, src/scene, src/vpp include only their own and lower layers and rooms")
