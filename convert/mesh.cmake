# Mesh (glTF) voxelization: vx_conv_mesh_core is the voxelizer alone (no octree
# builder), vx_conv_mesh adds scene assembly through vx_svo.
if(TARGET vx_gltf)
  find_package(Threads REQUIRED)
  add_library(vx_conv_mesh_core STATIC ${CMAKE_CURRENT_LIST_DIR}/mesh_voxelize.c ${CMAKE_CURRENT_LIST_DIR}/mesh_cells.c
              ${CMAKE_CURRENT_LIST_DIR}/mesh_material.c)
  target_link_libraries(vx_conv_mesh_core PUBLIC vx_core vx_gltf Threads::Threads m)
  add_library(vx_conv_mesh STATIC ${CMAKE_CURRENT_LIST_DIR}/mesh.c)
  target_link_libraries(vx_conv_mesh PUBLIC vx_conv_mesh_core vx_svo vx_gltf)
endif()
