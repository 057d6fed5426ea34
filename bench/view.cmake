# svo_view benchmarks: edit + scene update for many instances (view_bench);
# viewer frame time against svo_render: bench/view_bench.sh. With Dear ImGui
# (libimgui-dev, static) --loop also times the panels drawn on the GPU.
if(VX_WITH_VULKAN)
  add_executable(view_bench ${CMAKE_CURRENT_LIST_DIR}/view_bench.c ${CMAKE_SOURCE_DIR}/tools/svo_view/editor.c
                            ${CMAKE_SOURCE_DIR}/tools/svo_view/voxels.c ${CMAKE_SOURCE_DIR}/tools/svo_view/batch.c)
  target_link_libraries(view_bench PRIVATE vx_render vx_svo m)
  if(VX_WITH_IMGUI)
    find_package(PkgConfig QUIET)
    if(PKG_CONFIG_FOUND)
      pkg_check_modules(VX_IMGUI_BENCH QUIET IMPORTED_TARGET imgui)
    endif()
    find_path(VX_GLFW_HEADER GLFW/glfw3.h)
    if(VX_IMGUI_BENCH_FOUND AND VX_GLFW_HEADER)
      target_sources(view_bench PRIVATE ${CMAKE_SOURCE_DIR}/tools/svo_view/ui.cpp ${CMAKE_SOURCE_DIR}/tools/svo_view/font.c)
      target_include_directories(view_bench PRIVATE ${VX_GLFW_HEADER})
      target_link_libraries(view_bench PRIVATE PkgConfig::VX_IMGUI_BENCH)
      target_compile_definitions(view_bench PRIVATE VX_BENCH_GPU_PANELS=1)
    endif()
  endif()
endif()
