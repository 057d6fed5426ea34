# svo_view benchmarks: edit + scene update for many instances (view_bench);
# viewer frame time against svo_render: bench/view_bench.sh.
if(VX_WITH_VULKAN)
  add_executable(view_bench ${CMAKE_CURRENT_LIST_DIR}/view_bench.c ${CMAKE_SOURCE_DIR}/tools/svo_view/editor.c
                            ${CMAKE_SOURCE_DIR}/tools/svo_view/voxels.c)
  target_link_libraries(view_bench PRIVATE vx_render vx_svo m)
endif()
