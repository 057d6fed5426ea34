# render/: the plain-C trace layer (library vx_trace: BVH, CPU reference,
# camera maths, the compact GPU layout built on the CPU; no Vulkan) and the
# Vulkan compute tracer (library vx_render).
add_library(vx_trace STATIC
  ${CMAKE_CURRENT_SOURCE_DIR}/render_common.c
  ${CMAKE_CURRENT_SOURCE_DIR}/bvh.c
  ${CMAKE_CURRENT_SOURCE_DIR}/grid.c
  ${CMAKE_CURRENT_SOURCE_DIR}/cpu_trace.c
  ${CMAKE_CURRENT_SOURCE_DIR}/compact.c
  ${CMAKE_CURRENT_SOURCE_DIR}/compact_page.c
  ${CMAKE_CURRENT_SOURCE_DIR}/compact_trace.c)
target_link_libraries(vx_trace PUBLIC vx_svo m)
if(VX_WITH_VULKAN)
  find_package(Vulkan REQUIRED)

  # GLSL -> SPIR-V at build time, embedded as C arrays (no shader files to lose; cmake/shaders.cmake's
  # vx_spirv_header, whose depfile lists the includes).
  set(VX_RENDER_SPV_DIR ${CMAKE_CURRENT_BINARY_DIR}/spv)
  file(MAKE_DIRECTORY ${VX_RENDER_SPV_DIR})
  set(VX_RENDER_SPV_HEADERS)
  # name:source[:define]; trace_precise is trace.comp in float64 (deep models);
  # beam is the primary rays' beam pass (before trace).
  # gbuffer, direct, ao, resolve, post and frame (the merged gbuffer+direct+resolve)
  # are the pass pipeline's shaders (pipeline.c); cull builds its light grid;
  # display turns an image into display bytes on the GPU (display.c); display_image
  # writes them into the image shown (a storage image) instead of a buffer;
  # frame_display, resolve_display and post_display are those passes when they
  # are the frame's last and write the image shown themselves (display_out.glsl);
  # refit recomputes the instance BVH's bounds on the GPU (render_scene.c), inst_rows the instances' rows;
  # trace_compact traces the compact layout (render/compact.h, compact_gpu.c);
  # smap builds the directional light's depth map that clips shadow rays (shadow_map.c).
  foreach(spec trace:trace beam:beam dense:dense trace_precise:trace:PRECISE
               gbuffer:gbuffer direct:direct ao:ao resolve:resolve post:post frame:frame cull:cull
               display:display display_image:display:TO_IMAGE
               frame_display:frame:DISPLAY_OUT resolve_display:resolve:DISPLAY_OUT post_display:post:DISPLAY_OUT
               refit:refit inst_rows:inst_rows trace_compact:trace_compact smap:smap)
    vx_shader_spec(${spec} shader file defs ${VX_RENDER_SPV_DIR})
    set(src ${CMAKE_CURRENT_SOURCE_DIR}/shaders/${file}.comp)
    set(out ${VX_RENDER_SPV_DIR}/${shader}.comp.h)
    vx_spirv_header(${out} ${src} vx__${shader}_spv_arr DEFINES ${defs} COMMENT "glslangValidator ${shader}.comp")
    list(APPEND VX_RENDER_SPV_HEADERS ${out})
  endforeach()

  add_library(vx_render STATIC
    ${CMAKE_CURRENT_SOURCE_DIR}/gpu_device.c
    ${CMAKE_CURRENT_SOURCE_DIR}/gpu_memory.c
    ${CMAKE_CURRENT_SOURCE_DIR}/gpu_pipeline.c
    ${CMAKE_CURRENT_SOURCE_DIR}/gpu_dispatch.c
    ${CMAKE_CURRENT_SOURCE_DIR}/render_scene.c
    ${CMAKE_CURRENT_SOURCE_DIR}/pipeline.c
    ${CMAKE_CURRENT_SOURCE_DIR}/display.c
    ${CMAKE_CURRENT_SOURCE_DIR}/compact_gpu.c
    ${CMAKE_CURRENT_SOURCE_DIR}/shadow_map.c
    ${VX_RENDER_SPV_HEADERS})
  target_include_directories(vx_render PRIVATE ${VX_RENDER_SPV_DIR})
  target_link_libraries(vx_render PUBLIC vx_trace vx_svo Vulkan::Vulkan m)
  # The modules specialised on the host before the driver sees them (render/spirv_opt.h: lavapipe's start-up);
  # SPIRV-Tools' optimizer (Debian's spirv-tools, static libraries) where found, else none.
  find_package(SPIRV-Tools-opt QUIET CONFIG)
  if(TARGET SPIRV-Tools-opt)
    target_sources(vx_render PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/spirv_opt.cpp)
    target_link_libraries(vx_render PRIVATE SPIRV-Tools-opt)
    message(STATUS "voxkit: SPIR-V specialisation on the host (SPIRV-Tools-opt)")
  else()
    target_sources(vx_render PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/spirv_opt_none.c)
    message(STATUS "voxkit: no SPIRV-Tools-opt: pipelines made from the modules as built")
  endif()
endif()
