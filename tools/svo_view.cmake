# svo_view: interactive viewer and scene editor (GLFW window, Vulkan swapchain).
find_package(PkgConfig QUIET)
if(PKG_CONFIG_FOUND)
  pkg_check_modules(VX_GLFW QUIET IMPORTED_TARGET glfw3)
endif()
if(VX_WITH_VULKAN AND TARGET vx_image AND VX_GLFW_FOUND)
  add_executable(svo_view ${CMAKE_CURRENT_LIST_DIR}/svo_view/main.c ${CMAKE_CURRENT_LIST_DIR}/svo_view/present.c
                          ${CMAKE_CURRENT_LIST_DIR}/svo_view/editor.c ${CMAKE_CURRENT_LIST_DIR}/svo_view/font.c)
  target_link_libraries(svo_view PRIVATE vx_probes vx_render vx_tool_conv vx_image vx_tool PkgConfig::VX_GLFW m)
endif()
