# photons/: photon mapping on the GPU (global and caustic maps in hashed
# grids, progressive radius), the pass pipeline's gi=photons. shaders/photon.comp
# includes render/shaders/trace_common.glsl (the scene and its traversal) and
# probes/shaders/path_common.glsl (the path tracer's materials); embedded as
# a C array like render's and probes'.
if(VX_WITH_VULKAN)
  set(VX_PHOTONS_SPV_DIR ${CMAKE_CURRENT_BINARY_DIR}/spv)
  file(MAKE_DIRECTORY ${VX_PHOTONS_SPV_DIR})
  set(defs)
  vx_walk_defs(photon defs ${VX_PHOTONS_SPV_DIR}/photon.comp.h) # cmake/shaders.cmake: the walk non-contracted
  add_custom_command(
    OUTPUT ${VX_PHOTONS_SPV_DIR}/photon.comp.h
    COMMAND ${GLSLANG_VALIDATOR} -V --target-env ${VX_SPIRV_TARGET_ENV} -I${CMAKE_SOURCE_DIR}/render/shaders
            -I${CMAKE_SOURCE_DIR}/probes/shaders ${defs} --vn vx__photon_spv_arr -o ${VX_PHOTONS_SPV_DIR}/photon.comp.h
            ${CMAKE_CURRENT_LIST_DIR}/shaders/photon.comp
    DEPENDS ${CMAKE_CURRENT_LIST_DIR}/shaders/photon.comp ${CMAKE_SOURCE_DIR}/probes/shaders/path_common.glsl ${CMAKE_SOURCE_DIR}/render/shaders/sky.glsl ${CMAKE_SOURCE_DIR}/render/shaders/sampling.glsl
            ${CMAKE_SOURCE_DIR}/render/shaders/trace_common.glsl ${CMAKE_SOURCE_DIR}/render/shaders/compact_attr.glsl
    COMMENT "glslangValidator photon.comp"
    VERBATIM)
  add_library(vx_photons STATIC ${CMAKE_CURRENT_LIST_DIR}/photons.c ${VX_PHOTONS_SPV_DIR}/photon.comp.h)
  target_include_directories(vx_photons PRIVATE ${VX_PHOTONS_SPV_DIR})
  target_link_libraries(vx_photons PUBLIC vx_probes vx_render vx_svo m)
endif()
