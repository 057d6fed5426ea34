# Mesh voxelization benchmark (bench/mesh_bench.sh runs it).
if(TARGET vx_conv_mesh)
  add_executable(mesh_bench ${CMAKE_CURRENT_LIST_DIR}/mesh_bench.c)
  target_link_libraries(mesh_bench PRIVATE vx_conv_mesh m)
endif()
