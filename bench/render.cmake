# Tracer benchmark: needs only libvulkan and libc (no OpenImageIO/OpenVDB/GLFW),
# so the binary runs on a GPU machine that has just a Vulkan loader.
if(VX_WITH_VULKAN)
  add_executable(render_bench ${CMAKE_CURRENT_LIST_DIR}/render_bench.c)
  target_link_libraries(render_bench PRIVATE vx_render vx_convert vx_formats vx_svo)
endif()
