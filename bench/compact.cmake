# GPU bytes per voxel of the compact layout against today's (issue 18); CPU only.
add_executable(compact_bench ${CMAKE_CURRENT_LIST_DIR}/compact_bench.c)
target_link_libraries(compact_bench PRIVATE vx_trace vx_convert vx_formats vx_svo)
