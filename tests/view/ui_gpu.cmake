# svo_view's panels drawn on the GPU (tools/svo_view/ui.h ui_gpu_record, Dear
# ImGui's Vulkan backend) against the frame without panels and the CPU
# rasterizer, on lavapipe; built where svo_view's panels are (libimgui-dev,
# GLFW's header for the shim's key codes).
if(VX_WITH_VULKAN AND VX_WITH_IMGUI)
  find_package(PkgConfig QUIET)
  if(PKG_CONFIG_FOUND)
    pkg_check_modules(VX_IMGUI_TEST QUIET IMPORTED_TARGET imgui)
  endif()
  find_path(VX_GLFW_HEADER GLFW/glfw3.h)
  if(VX_IMGUI_TEST_FOUND AND VX_GLFW_HEADER)
    vx_add_test(test_ui_gpu SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_ui_gpu.c ${CMAKE_SOURCE_DIR}/tools/svo_view/ui.cpp
                ${CMAKE_SOURCE_DIR}/tools/svo_view/font.c LIBS vx_render vx_svo PkgConfig::VX_IMGUI_TEST m)
    target_include_directories(test_ui_gpu PRIVATE ${VX_GLFW_HEADER})
    set_tests_properties(test_ui_gpu PROPERTIES ENVIRONMENT
                         "LSAN_OPTIONS=suppressions=${CMAKE_SOURCE_DIR}/tests/render/lsan.supp")
  endif()
endif()
