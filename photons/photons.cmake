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
  vx_spirv_header(${VX_PHOTONS_SPV_DIR}/photon.comp.h ${CMAKE_CURRENT_LIST_DIR}/shaders/photon.comp vx__photon_spv_arr
                  INCLUDES ${CMAKE_SOURCE_DIR}/render/shaders ${CMAKE_SOURCE_DIR}/probes/shaders DEFINES ${defs})
  # the same kernel without the trace and the camera's paths: the small steps' module (photon.comp says why)
  vx_spirv_header(${VX_PHOTONS_SPV_DIR}/photon_small.comp.h ${CMAKE_CURRENT_LIST_DIR}/shaders/photon.comp
                  vx__photon_small_spv_arr INCLUDES ${CMAKE_SOURCE_DIR}/render/shaders ${CMAKE_SOURCE_DIR}/probes/shaders
                  DEFINES ${defs} -DPHOTON_SMALL COMMENT "glslangValidator photon.comp (PHOTON_SMALL)")
  add_library(vx_photons STATIC ${CMAKE_CURRENT_LIST_DIR}/photons.c ${VX_PHOTONS_SPV_DIR}/photon.comp.h
              ${VX_PHOTONS_SPV_DIR}/photon_small.comp.h)
  target_include_directories(vx_photons PRIVATE ${VX_PHOTONS_SPV_DIR})
  target_link_libraries(vx_photons PUBLIC vx_probes vx_render vx_svo m)
endif()
