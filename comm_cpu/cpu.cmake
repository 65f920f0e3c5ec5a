# The 8086-2 core (plain C++, no SystemC), the SingleStepTests runner and the SystemC module.
add_library(rcsim_cpu8086_core STATIC
  ${CMAKE_CURRENT_LIST_DIR}/i8086_biu.cpp
  ${CMAKE_CURRENT_LIST_DIR}/i8086_eu.cpp
  ${CMAKE_CURRENT_LIST_DIR}/i8086_exec.cpp
  ${CMAKE_CURRENT_LIST_DIR}/i8086_muldiv.cpp
  ${CMAKE_CURRENT_LIST_DIR}/i8086_ops_alu.cpp
  ${CMAKE_CURRENT_LIST_DIR}/i8086_ops_control.cpp
  ${CMAKE_CURRENT_LIST_DIR}/i8086_ops_move.cpp
  ${CMAKE_CURRENT_LIST_DIR}/sst.cpp
  ${CMAKE_SOURCE_DIR}/models/memory.cpp
)
target_include_directories(rcsim_cpu8086_core PUBLIC ${CMAKE_SOURCE_DIR})
target_link_libraries(rcsim_cpu8086_core PUBLIC nlohmann_json::nlohmann_json ZLIB::ZLIB)

add_library(rcsim_comm_cpu STATIC
  ${CMAKE_CURRENT_LIST_DIR}/cputest_cmd.cpp
  ${CMAKE_CURRENT_LIST_DIR}/bench_cpu.cpp
)
target_include_directories(rcsim_comm_cpu PUBLIC ${CMAKE_SOURCE_DIR})
target_link_libraries(rcsim_comm_cpu PUBLIC rcsim_cpu8086_core rcsim_models CLI11::CLI11)
target_sources(rcsim_comm_cpu PRIVATE ${CMAKE_CURRENT_LIST_DIR}/cpu8086.cpp)
