# Tracer benchmark: needs only libvulkan and libc (no OpenImageIO/OpenVDB/GLFW),
# so the binary runs on a GPU machine that has just a Vulkan loader. The ESVO
# baseline's kernel (bench/shaders/esvo.comp) is embedded like render's shaders.
if(VX_WITH_VULKAN)
  set(VX_BENCH_SPV_DIR ${CMAKE_CURRENT_BINARY_DIR}/spv)
  file(MAKE_DIRECTORY ${VX_BENCH_SPV_DIR})
  foreach(name esvo tree64 mipgrid brickgrid)
    vx_spirv_header(${VX_BENCH_SPV_DIR}/${name}.comp.h ${CMAKE_CURRENT_LIST_DIR}/shaders/${name}.comp vx__${name}_spv_arr)
  endforeach()
  add_executable(render_bench ${CMAKE_CURRENT_LIST_DIR}/render_bench.c ${CMAKE_CURRENT_LIST_DIR}/esvo.c
                 ${CMAKE_CURRENT_LIST_DIR}/tree64.c ${CMAKE_CURRENT_LIST_DIR}/mipgrid.c ${CMAKE_CURRENT_LIST_DIR}/brickgrid.c
                 ${VX_BENCH_SPV_DIR}/esvo.comp.h ${VX_BENCH_SPV_DIR}/tree64.comp.h ${VX_BENCH_SPV_DIR}/mipgrid.comp.h ${VX_BENCH_SPV_DIR}/brickgrid.comp.h)
  target_include_directories(render_bench PRIVATE ${VX_BENCH_SPV_DIR})
  target_link_libraries(render_bench PRIVATE vx_render vx_convert vx_formats vx_svo)
endif()
# Issue 18's speed goal as written (the tracer of the day the issue was filed): trace.comp's albedo rays/s on
# compact_bench's views; the same source builds in that day's tree (bench/today_bench.c says how).
if(VX_WITH_VULKAN)
  add_executable(today_bench ${CMAKE_CURRENT_LIST_DIR}/today_bench.c)
  target_link_libraries(today_bench PRIVATE vx_render vx_convert vx_formats vx_svo)
endif()
