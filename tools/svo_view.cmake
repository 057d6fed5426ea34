# svo_view: interactive viewer and scene editor (GLFW window, Vulkan swapchain),
# with Dear ImGui panels where libimgui-dev is found (VX_WITH_IMGUI; without
# it the viewer keeps its text overlay: panels_none.c).
find_package(PkgConfig QUIET)
if(PKG_CONFIG_FOUND)
  pkg_check_modules(VX_GLFW QUIET IMPORTED_TARGET glfw3)
  if(VX_WITH_IMGUI)
    pkg_check_modules(VX_IMGUI QUIET IMPORTED_TARGET imgui)
  endif()
endif()
if(VX_WITH_VULKAN AND TARGET vx_image AND VX_GLFW_FOUND)
  set(_sv ${CMAKE_CURRENT_LIST_DIR}/svo_view)
  add_executable(svo_view ${_sv}/main.c ${_sv}/options.c ${_sv}/scene.c ${_sv}/probes.c ${_sv}/camera.c
                          ${_sv}/frame.c ${_sv}/input.c ${_sv}/script.c ${_sv}/present.c ${_sv}/editor.c ${_sv}/voxels.c ${_sv}/font.c ${_sv}/settings.c
                          ${_sv}/batch.c)
  target_link_libraries(svo_view PRIVATE vx_photons vx_cones vx_probes vx_render vx_tool_conv vx_conv_export vx_image vx_tool
                        PkgConfig::VX_GLFW m)
  if(VX_WITH_IMGUI AND VX_IMGUI_FOUND)
    target_sources(svo_view PRIVATE ${_sv}/panels.c ${_sv}/ui.cpp)
    target_link_libraries(svo_view PRIVATE PkgConfig::VX_IMGUI)
    set_property(TARGET svo_view PROPERTY VX_PANELS 1) # tests/view reads it
    message(STATUS "svo_view: panels with Dear ImGui ${VX_IMGUI_VERSION}")
  else()
    target_sources(svo_view PRIVATE ${_sv}/panels_none.c)
    set_property(TARGET svo_view PROPERTY VX_PANELS 0)
    message(STATUS "svo_view: no panels (Dear ImGui not found or VX_WITH_IMGUI off)")
  endif()
endif()
