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
    vx_spirv_header(${VX_PROBES_SPV_DIR}/${name}.comp.h ${CMAKE_CURRENT_LIST_DIR}/shaders/${name}.comp vx__${name}_spv_arr)
  endforeach()
  # probe.comp three times: probe, the bake's kernel; probe_one, the bake's one-walk kernel (bake_one(),
  # scenes without lights, emitters, metal or glass: the driver compiles one walk instead of four); probe_pt,
  # the render passes' (GPU path tracer, GI, light field: PT_PRECISE). Every float operation of each one's path
  # and walk is precise (probe.comp says why: the same bits with and without the sun's depth map and in both
  # layouts on NVIDIA)
  # (NAME:FILE[:DEFINE], as render/render.cmake's list: cmake/shaders.cmake)
  foreach(spec probe:probe probe_pt:probe:PT_PRECISE probe_one:probe:VX_ONE_WALK)
    vx_shader_spec(${spec} name file defs)
    vx_spirv_header(${VX_PROBES_SPV_DIR}/${name}.comp.h ${CMAKE_CURRENT_LIST_DIR}/shaders/${file}.comp vx__${name}_spv_arr
                    INCLUDES ${CMAKE_SOURCE_DIR}/render/shaders DEFINES ${defs} COMMENT "glslangValidator ${name}.comp")
  endforeach()
  # shaders/probe_beam.comp includes render/shaders/beam.comp's walk, made an include by beam_body.cmake
  add_custom_command(
    OUTPUT ${VX_PROBES_SPV_DIR}/beam_body.glsl
    COMMAND ${CMAKE_COMMAND} -DIN=${CMAKE_SOURCE_DIR}/render/shaders/beam.comp -DOUT=${VX_PROBES_SPV_DIR}/beam_body.glsl
            -P ${CMAKE_CURRENT_LIST_DIR}/shaders/beam_body.cmake
    DEPENDS ${CMAKE_SOURCE_DIR}/render/shaders/beam.comp ${CMAKE_CURRENT_LIST_DIR}/shaders/beam_body.cmake
    COMMENT "beam_body.glsl from beam.comp"
    VERBATIM)
  vx_spirv_header(${VX_PROBES_SPV_DIR}/probe_beam.comp.h ${CMAKE_CURRENT_LIST_DIR}/shaders/probe_beam.comp
                  vx__probe_beam_spv_arr INCLUDES ${CMAKE_SOURCE_DIR}/render/shaders ${VX_PROBES_SPV_DIR}
                  DEPENDS ${VX_PROBES_SPV_DIR}/beam_body.glsl)
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
    ${VX_PROBES_SPV_DIR}/probe_pt.comp.h
    ${VX_PROBES_SPV_DIR}/probe_one.comp.h
    ${VX_PROBES_SPV_DIR}/probe_out.comp.h
    ${VX_PROBES_SPV_DIR}/probe_filter.comp.h
    ${VX_PROBES_SPV_DIR}/probe_beam.comp.h)
  target_include_directories(vx_probes PRIVATE ${VX_PROBES_SPV_DIR})
  target_link_libraries(vx_probes PUBLIC vx_render vx_svo Threads::Threads m)
  # the file's CRC-32 by libdeflate's carry-less multiply where svo/ links it (6.6 MB in 0.4 ms against 2.6 ms
  # by the table): the bake's last batch is checksummed after the GPU's last batch
  if(VX_WITH_LIBDEFLATE AND VX_LIBDEFLATE_INCLUDE AND VX_LIBDEFLATE_LIB)
    target_include_directories(vx_probes PRIVATE ${VX_LIBDEFLATE_INCLUDE})
    target_compile_definitions(vx_probes PRIVATE VX_HAVE_LIBDEFLATE=1)
  endif()
endif()
