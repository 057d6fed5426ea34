# Greedy meshing of voxels (formats/voxmesh.h, library vx_voxmesh) and the
# .glb writer over Debian's tinygltf (formats/glb.h, library vx_glb, where
# gltf.cmake found tinygltf): svo_info --to-glb.
add_library(vx_voxmesh STATIC ${CMAKE_CURRENT_LIST_DIR}/voxmesh.c)
target_link_libraries(vx_voxmesh PUBLIC vx_core)
if(TARGET vx_gltf)
  add_library(vx_glb STATIC ${CMAKE_CURRENT_LIST_DIR}/glb_tinygltf.cpp)
  target_include_directories(vx_glb PRIVATE ${VX_TINYGLTF_INCLUDE})
  target_link_libraries(vx_glb PUBLIC vx_core PRIVATE ${VX_TINYGLTF_LIB})
endif()
