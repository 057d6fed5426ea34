# svo_bake: bake light field probes for a .svo scene (CPU), shards and merge.
if(VX_WITH_VULKAN AND VX_WITH_OIIO)
  add_executable(svo_bake ${CMAKE_CURRENT_LIST_DIR}/svo_bake/main.c)
  target_link_libraries(svo_bake PRIVATE vx_probes vx_image vx_tool vx_svo)
endif()
