# Runs ld86 and keeps its -M symbol listing (printed on stdout) in MAP.
# cmake -DLD86=... -DOUT=image -DMAP=map.txt -DOBJS="a.o;b.o" -P ld86.cmake
execute_process(
  COMMAND ${LD86} -0 -d -i -T 0 -D 0 -M -o ${OUT} ${OBJS}
  OUTPUT_FILE ${MAP}
  ERROR_VARIABLE err
  RESULT_VARIABLE rc)
if(NOT rc EQUAL 0 OR err)
  file(REMOVE ${OUT})
  message(FATAL_ERROR "ld86 failed (${rc}): ${err}")
endif()
