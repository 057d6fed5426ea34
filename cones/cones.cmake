# cones/: voxel cone tracing (issue 12): the radiance volume beside the
# octrees and the gi=cones pass. Its shaders include render/shaders' scene
# bindings, traversal and lights; embedded as C arrays like render's.
if(VX_WITH_VULKAN)
  set(VX_CONES_SPV_DIR ${CMAKE_CURRENT_BINARY_DIR}/spv)
  file(MAKE_DIRECTORY ${VX_CONES_SPV_DIR})
  set(VX_CONES_SPV)
  foreach(name voxelize inject filter cone)
    set(var ${name})
    if(name STREQUAL "cone")
      set(var trace)
    endif()
    set(defs)
    vx_walk_defs(cone_${var} defs ${VX_CONES_SPV_DIR}/${name}.comp.h) # cmake/shaders.cmake: the walk non-contracted
    vx_spirv_header(${VX_CONES_SPV_DIR}/${name}.comp.h ${CMAKE_CURRENT_LIST_DIR}/shaders/${name}.comp vx__cone_${var}_spv_arr
                    INCLUDES ${CMAKE_SOURCE_DIR}/render/shaders ${CMAKE_CURRENT_LIST_DIR}/shaders DEFINES ${defs}
                    COMMENT "glslangValidator cones/${name}.comp")
    list(APPEND VX_CONES_SPV ${VX_CONES_SPV_DIR}/${name}.comp.h)
  endforeach()
  add_library(vx_cones STATIC ${CMAKE_CURRENT_LIST_DIR}/cones.c ${VX_CONES_SPV})
  target_include_directories(vx_cones PRIVATE ${VX_CONES_SPV_DIR})
  target_link_libraries(vx_cones PUBLIC vx_probes vx_render vx_svo m)
endif()
