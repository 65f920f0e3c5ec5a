# The include rules of the tree (docs/architecture.md, "Layers"): every directory may include its
# own headers and those of the floors below it, never a floor above or beside it.
#
#   scenarios/  the top: assembles, measures, reports          -> everything
#   comm_cpu/   the communication board                        -> comm_cpu pic8259 uart82510 dpram models
#   main_cpu/   the main board                                 -> main_cpu camc_qi models
#   pic8259/ dpram/ uart82510/ camc_qi/   one chip model each  -> itself, models
#   models/     the ground floor                               -> models
#
# The 8086 core is the folder comm_cpu/i8086/, and it is plain C++: it includes no SystemC or TLM
# header and, of the tree, only itself and the plain C++ headers models/memory.h and models/plumbing/hex.h.
# Core code lives nowhere else: outside that folder, a source named i8086* or one that includes
# the core's private microcode steps (comm_cpu/i8086/microcode.h) is a violation.
#
# Inside scenarios/ the same rule holds between its code folders (scenarios/README.md), each of
# which may include the floors of the tree and these folders of scenarios/:
#
#   host/                                  -> host
#   board/                                 -> board
#   debug/                                 -> debug host
#   bound/    the static bound             -> bound debug host
#   config/                                -> config board host
#   world/    the simulated world          -> world config board host
#   verdict/  what decides PASS            -> verdict world config board host
#   report/   what renders                 -> report verdict config board host   (never world)
#   trace/ monitor/                        -> itself and the folders above but run, sweep, cli
#   coverage/                              -> coverage trace report verdict world config board debug host
#   modbus/                                -> modbus monitor and the folders monitor may include
#   run/                                   -> every folder above but sweep, search, cli
#   sweep/                                 -> sweep run coverage report verdict config board host
#   search/                                -> search and the folders sweep may include
#   cli/                                   -> every folder
#
# and the root of scenarios/ holds data only: a .cpp or .h there is a violation.
#
# Usage: cmake -DROOT=<source tree> -P check_layers.cmake. Prints every offending file:line and
# fails; prints "layers: N files, 0 violations" otherwise.
cmake_minimum_required(VERSION 3.25)
if(NOT ROOT)
  message(FATAL_ERROR "usage: cmake -DROOT=<source tree> -P check_layers.cmake")
endif()

set(allowed_models    models)
set(allowed_pic8259   pic8259 models)
set(allowed_dpram     dpram models)
set(allowed_uart82510 uart82510 models)
set(allowed_camc_qi   camc_qi models)
set(allowed_comm_cpu  comm_cpu pic8259 uart82510 dpram models)
set(allowed_main_cpu  main_cpu camc_qi models)
set(layers models pic8259 dpram uart82510 camc_qi comm_cpu main_cpu)
# The headers of models/ the plain C++ 8086 core may include (no SystemC behind them).
set(core_models models/memory.h models/plumbing/hex.h)
set(tree_dirs models pic8259 dpram uart82510 camc_qi comm_cpu main_cpu scenarios tests)

set(sc_host    host)
set(sc_board   board)
set(sc_debug   debug host)
set(sc_bound   bound debug host)
set(sc_config  config board host)
set(sc_world   world config board host)
set(sc_verdict verdict world config board host)
set(sc_report  report verdict config board host)
set(sc_trace   trace report verdict world config board debug host)
set(sc_monitor monitor report verdict world config board host)
set(sc_coverage coverage trace report verdict world config board debug host)
set(sc_modbus  modbus monitor report verdict world config board host)
set(sc_run     run bound coverage trace modbus monitor report verdict world config board debug host)
set(sc_sweep   sweep run coverage report verdict config board host)
set(sc_search  search sweep run coverage report verdict config board host)
set(sc_cli     cli bound search sweep run coverage trace modbus monitor report verdict world config board debug host)
set(sc_folders host board debug bound config world verdict report trace monitor modbus coverage run sweep search cli)

set(violations 0)
set(files_seen 0)

# check_file(FILE LAYER): every `#include "dir/..."` of the tree must name an allowed dir.
function(check_file file layer)
  file(RELATIVE_PATH rel "${ROOT}" "${file}")
  file(STRINGS "${file}" all_lines)
  set(n 0)
  set(bad ${violations})
  set(core FALSE)
  if(rel MATCHES "^comm_cpu/i8086/")
    set(core TRUE)
  else()
    get_filename_component(name "${rel}" NAME)
    if(name MATCHES "^i8086")
      message("${rel}: core code outside comm_cpu/i8086/ (the core's folder)")
      math(EXPR bad "${bad} + 1")
    endif()
  endif()
  foreach(line IN LISTS all_lines)
    math(EXPR n "${n} + 1")
    if(NOT line MATCHES "^[ \t]*#[ \t]*include[ \t]*([<\"])([^>\"]+)[>\"]")
      continue()
    endif()
    set(quote "${CMAKE_MATCH_1}") # each MATCHES below resets CMAKE_MATCH_n
    set(header "${CMAKE_MATCH_2}")
    if(core AND (header MATCHES "^(systemc|tlm)" OR (quote STREQUAL "\"" AND
        NOT header MATCHES "^comm_cpu/i8086/" AND NOT header IN_LIST core_models)))
      message("${rel}:${n}: the plain C++ 8086 core includes ${header}")
      math(EXPR bad "${bad} + 1")
      continue()
    endif()
    if(NOT core AND header STREQUAL "comm_cpu/i8086/microcode.h")
      message("${rel}:${n}: core code outside comm_cpu/i8086/ (includes the core's private ${header})")
      math(EXPR bad "${bad} + 1")
      continue()
    endif()
    if(NOT quote STREQUAL "\"" OR NOT header MATCHES "^([A-Za-z0-9_]+)/")
      continue()
    endif()
    set(dir "${CMAKE_MATCH_1}")
    if(NOT dir IN_LIST tree_dirs)
      continue() # a generated header of the build tree (comm_cpu/firmware/... is caught above)
    endif()
    if(NOT dir IN_LIST allowed_${layer})
      message("${rel}:${n}: ${layer}/ includes ${header} (${dir}/ is not below ${layer}/)")
      math(EXPR bad "${bad} + 1")
    endif()
  endforeach()
  set(violations ${bad} PARENT_SCOPE)
endfunction()

# check_scenarios_file(FILE FOLDER): every `#include "scenarios/<sub>/..."` must name a folder of
# sc_<FOLDER>.
function(check_scenarios_file file folder)
  file(RELATIVE_PATH rel "${ROOT}" "${file}")
  file(STRINGS "${file}" all_lines)
  set(n 0)
  set(bad ${violations})
  foreach(line IN LISTS all_lines)
    math(EXPR n "${n} + 1")
    if(NOT line MATCHES "^[ \t]*#[ \t]*include[ \t]*\"scenarios/([^\"]+)\"")
      continue()
    endif()
    set(header "scenarios/${CMAKE_MATCH_1}")
    if(NOT CMAKE_MATCH_1 MATCHES "^([A-Za-z0-9_]+)/")
      message("${rel}:${n}: scenarios/${folder}/ includes ${header} (the root of scenarios/ holds no code)")
      math(EXPR bad "${bad} + 1")
      continue()
    endif()
    if(NOT CMAKE_MATCH_1 IN_LIST sc_${folder})
      message("${rel}:${n}: scenarios/${folder}/ includes ${header} (scenarios/${CMAKE_MATCH_1}/ is not below scenarios/${folder}/)")
      math(EXPR bad "${bad} + 1")
    endif()
  endforeach()
  set(violations ${bad} PARENT_SCOPE)
endfunction()

foreach(layer IN LISTS layers)
  file(GLOB_RECURSE sources LIST_DIRECTORIES false
    "${ROOT}/${layer}/*.h" "${ROOT}/${layer}/*.hpp" "${ROOT}/${layer}/*.cpp" "${ROOT}/${layer}/*.c")
  list(SORT sources)
  foreach(f IN LISTS sources)
    math(EXPR files_seen "${files_seen} + 1")
    check_file("${f}" ${layer})
  endforeach()
endforeach()

file(GLOB root_code LIST_DIRECTORIES false "${ROOT}/scenarios/*.h" "${ROOT}/scenarios/*.cpp")
list(SORT root_code)
foreach(f IN LISTS root_code)
  file(RELATIVE_PATH rel "${ROOT}" "${f}")
  message("${rel}: code at the root of scenarios/, which holds data only (scenarios/README.md)")
  math(EXPR files_seen "${files_seen} + 1")
  math(EXPR violations "${violations} + 1")
endforeach()
file(GLOB sc_dirs LIST_DIRECTORIES true "${ROOT}/scenarios/*")
list(SORT sc_dirs)
foreach(d IN LISTS sc_dirs)
  if(NOT IS_DIRECTORY "${d}")
    continue()
  endif()
  get_filename_component(folder "${d}" NAME)
  file(GLOB_RECURSE sources LIST_DIRECTORIES false "${d}/*.h" "${d}/*.cpp")
  list(SORT sources)
  if(sources AND NOT folder IN_LIST sc_folders)
    message("scenarios/${folder}/: a code folder the layer rules do not name (tests/layout/check_layers.cmake)")
    math(EXPR violations "${violations} + 1")
    continue()
  endif()
  foreach(f IN LISTS sources)
    math(EXPR files_seen "${files_seen} + 1")
    check_scenarios_file("${f}" ${folder})
  endforeach()
endforeach()

if(files_seen EQUAL 0)
  message(FATAL_ERROR "layers: no source files under ${ROOT}: nothing was checked")
endif()
if(violations GREATER 0)
  message(FATAL_ERROR "layers: ${violations} include(s) break the layer rules (docs/architecture.md)")
endif()
message("layers: ${files_seen} files, 0 violations")
