add_executable(svo_build_bench ${CMAKE_CURRENT_SOURCE_DIR}/svo_build_bench.c)
target_link_libraries(svo_build_bench PRIVATE vx_svo)
add_executable(svo_io_bench ${CMAKE_CURRENT_SOURCE_DIR}/svo_io_bench.c)
target_link_libraries(svo_io_bench PRIVATE vx_svo)
