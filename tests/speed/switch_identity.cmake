# For each scenario in SCENARIOS and each switch in SWITCHES: writes a short copy (duration_s =
# DURATION, drain_s too, or the scenario's own with DURATION=keep; no real-time pacing) with
# `board: {SWITCH: false}` and one with `board: {SWITCH: true}`, runs both with
# `rcsim run --reproducible` and fails unless report.json and interrupts.csv are identical.
# The pseudo-switch `seed` varies the seed instead (1 vs 2): a difference the check must see.
# The pseudo-switch `binary` runs the same scenario with RCSIM and with RCSIM_OTHER (another
# build of the program).
foreach(var RCSIM SCENARIOS SWITCHES DURATION WORK)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "switch_identity.cmake: -D${var}=... is required")
  endif()
endforeach()
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})

function(write_variant src dst switch value)
  file(READ ${src} text)
  if(text MATCHES "\nboard:")
    message(FATAL_ERROR "${src}: has its own board: section; extend switch_identity.cmake to merge it")
  endif()
  if(NOT DURATION STREQUAL "keep")
    string(REGEX REPLACE "\nduration_s:[^\n]*" "\nduration_s: ${DURATION}" text "${text}")
    # The drain after the traffic as short as the traffic.
    string(REGEX REPLACE "\ndrain_s:[^\n]*" "\ndrain_s: ${DURATION}" text "${text}")
  endif()
  # No real-time pacing (a paced run takes wall time, not a different course); the monitor (if
  # any) on a free port.
  string(REGEX REPLACE "\nrealtime:[^\n]*" "" text "${text}")
  string(REGEX REPLACE "listen: \"127.0.0.1:[0-9]+\"" "listen: \"127.0.0.1:0\"" text "${text}")
  # The copy lives in WORK: a program file named relative to the scenario, made absolute.
  get_filename_component(srcdir ${src} DIRECTORY)
  string(REGEX REPLACE "\n( *)program: ([^/\n][^\n]*)" "\n\\1program: ${srcdir}/\\2" text "${text}")
  # ... and a replay host's log (`{host: replay, file: NAME}`).
  string(REGEX REPLACE "host: replay, file: ([^/ ,}\n][^ ,}\n]*)" "host: replay, file: ${srcdir}/\\1" text "${text}")
  if(switch STREQUAL "seed")
    string(REGEX REPLACE "\nseed:[^\n]*" "" text "${text}")
    set(text "${text}\nseed: ${value}\n")
  elseif(switch STREQUAL "binary")
    # the scenario as it is; the program differs
  else()
    set(text "${text}\nboard: {${switch}: ${value}}\n")
  endif()
  file(WRITE ${dst} "${text}")
endfunction()

set(failed "")
foreach(scenario IN LISTS SCENARIOS)
  get_filename_component(stem ${scenario} NAME_WE)
  foreach(switch IN LISTS SWITCHES)
    if(switch STREQUAL "seed")
      set(values 1 2)
    elseif(switch STREQUAL "binary")
      if(NOT DEFINED RCSIM_OTHER)
        message(FATAL_ERROR "switch_identity.cmake: the switch binary needs -DRCSIM_OTHER=...")
      endif()
      set(values first other)
    else()
      set(values false true)
    endif()
    foreach(value IN LISTS values)
      # The same file name in both variants: a scenario without a name: is named after it.
      set(dir ${WORK}/${switch}_${value}/${stem}.out)
      set(yaml ${WORK}/${switch}_${value}/${stem}.yaml)
      write_variant(${scenario} ${yaml} ${switch} ${value})
      set(program ${RCSIM})
      if(switch STREQUAL "binary" AND value STREQUAL "other")
        set(program ${RCSIM_OTHER})
      endif()
      execute_process(COMMAND ${program} run ${yaml} --out ${dir} --reproducible
                      RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
      if(NOT rc EQUAL 0 AND NOT rc EQUAL 1 AND NOT rc EQUAL 4)
        message(FATAL_ERROR "${yaml}: rcsim exited with ${rc}: ${err}")
      endif()
    endforeach()
    list(GET values 0 a)
    list(GET values 1 b)
    foreach(f report.json interrupts.csv)
      set(fa ${WORK}/${switch}_${a}/${stem}.out/${f})
      set(fb ${WORK}/${switch}_${b}/${stem}.out/${f})
      if(f STREQUAL "interrupts.csv" AND NOT EXISTS ${fa} AND NOT EXISTS ${fb})
        # A run of unknown length (duration_s: 0) writes it compressed (the same bytes for the
        # same rows); a motion-only scenario has no comm board and neither file.
        set(fa ${fa}.gz)
        set(fb ${fb}.gz)
        if(NOT EXISTS ${fa} AND NOT EXISTS ${fb})
          continue()
        endif()
      endif()
      if(NOT EXISTS ${fa} OR NOT EXISTS ${fb})
        # Not a difference: a run that wrote nothing (Speed.ComparisonDetectsADifference must not
        # pass on it).
        list(APPEND failed "${stem}: ${f} missing after the run with ${switch} ${a} or ${b}")
        continue()
      endif()
      execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${fa} ${fb} RESULT_VARIABLE diff)
      if(NOT diff EQUAL 0)
        list(APPEND failed "${stem}: ${f} differs with ${switch} ${a} vs ${b}")
      else()
        message(STATUS "${stem}: ${f} identical with ${switch} ${a} and ${b}")
      endif()
    endforeach()
  endforeach()
endforeach()
if(failed)
  string(REPLACE ";" "\n  " failed "${failed}")
  message(FATAL_ERROR "speed-up switches changed results:\n  ${failed}")
endif()
