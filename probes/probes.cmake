# probes/: light field probes (placement, CPU bake, .probes file, GI renderer).
if(VX_WITH_VULKAN)
  find_package(Threads REQUIRED)
  # shaders/probe.comp (bake and GI passes) includes render/shaders/trace_common.glsl
  # for the scene's bindings and traversal and shaders/path_common.glsl (materials, shared
  # with photons/); embedded as a C array like render's.
  set(VX_PROBES_SPV_DIR ${CMAKE_CURRENT_BINARY_DIR}/spv)
  file(MAKE_DIRECTORY ${VX_PROBES_SPV_DIR})
  # the shaders that include nothing: one rule each
  foreach(name probe_out probe_filter)
    add_custom_command(
      OUTPUT ${VX_PROBES_SPV_DIR}/${name}.comp.h
      COMMAND ${GLSLANG_VALIDATOR} -V --target-env vulkan1.1 --vn vx__${name}_spv_arr
              -o ${VX_PROBES_SPV_DIR}/${name}.comp.h ${CMAKE_CURRENT_LIST_DIR}/shaders/${name}.comp
      DEPENDS ${CMAKE_CURRENT_LIST_DIR}/shaders/${name}.comp
      COMMENT "glslangValidator ${name}.comp"
      VERBATIM)
  endforeach()
  add_custom_command(
    OUTPUT ${VX_PROBES_SPV_DIR}/probe.comp.h
    COMMAND ${GLSLANG_VALIDATOR} -V --target-env vulkan1.1 -I${CMAKE_SOURCE_DIR}/render/shaders
            --vn vx__probe_spv_arr -o ${VX_PROBES_SPV_DIR}/probe.comp.h ${CMAKE_CURRENT_LIST_DIR}/shaders/probe.comp
    DEPENDS ${CMAKE_CURRENT_LIST_DIR}/shaders/probe.comp ${CMAKE_CURRENT_LIST_DIR}/shaders/path_common.glsl
            ${CMAKE_SOURCE_DIR}/render/shaders/trace_common.glsl ${CMAKE_SOURCE_DIR}/render/shaders/sky.glsl ${CMAKE_SOURCE_DIR}/render/shaders/sampling.glsl
    COMMENT "glslangValidator probe.comp"
    VERBATIM)
  add_library(vx_probes STATIC
    ${CMAKE_CURRENT_LIST_DIR}/oct.c
    ${CMAKE_CURRENT_LIST_DIR}/light.c
    ${CMAKE_CURRENT_LIST_DIR}/pathtrace.c
    ${CMAKE_CURRENT_LIST_DIR}/bake.c
    ${CMAKE_CURRENT_LIST_DIR}/file.c
    ${CMAKE_CURRENT_LIST_DIR}/render_gi.c
    ${CMAKE_CURRENT_LIST_DIR}/lightfield.c
    ${CMAKE_CURRENT_LIST_DIR}/probe_gpu.c
    ${CMAKE_CURRENT_LIST_DIR}/gi_pass.c
    ${VX_PROBES_SPV_DIR}/probe.comp.h
    ${VX_PROBES_SPV_DIR}/probe_out.comp.h
    ${VX_PROBES_SPV_DIR}/probe_filter.comp.h)
  target_include_directories(vx_probes PRIVATE ${VX_PROBES_SPV_DIR})
  target_link_libraries(vx_probes PUBLIC vx_render vx_svo Threads::Threads m)
endif()
