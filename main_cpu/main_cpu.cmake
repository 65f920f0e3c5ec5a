# rcsim_main_cpu: the behavioural main CPU (DP-RAM driver, frame reassembly, token dispatcher,
# response frames, control cycle). Included by main_cpu/CMakeLists.txt.
add_library(rcsim_main_cpu STATIC
  ${CMAKE_CURRENT_LIST_DIR}/dispatcher.cpp
  ${CMAKE_CURRENT_LIST_DIR}/processor.cpp
  ${CMAKE_CURRENT_LIST_DIR}/main_cpu.cpp
)
target_include_directories(rcsim_main_cpu PUBLIC ${CMAKE_SOURCE_DIR})
target_link_libraries(rcsim_main_cpu PUBLIC rcsim_frame rcsim_models PkgConfig::SYSTEMC nlohmann_json::nlohmann_json)
