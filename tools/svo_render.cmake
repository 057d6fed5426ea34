# svo_render: render a .svo scene to PNG/EXR with the Vulkan tracer (or --cpu).
if(VX_WITH_VULKAN AND VX_WITH_OIIO)
  add_executable(svo_render ${CMAKE_CURRENT_SOURCE_DIR}/svo_render/main.c)
  target_link_libraries(svo_render PRIVATE vx_probes vx_render vx_image vx_tool_light vx_tool vx_svo)
endif()
