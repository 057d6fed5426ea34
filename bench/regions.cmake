# svo_regions: a generated scene of many grid-aligned region models (issue 18, many instances)
add_executable(svo_regions ${CMAKE_CURRENT_SOURCE_DIR}/svo_regions.c)
target_link_libraries(svo_regions PRIVATE vx_svo m)
