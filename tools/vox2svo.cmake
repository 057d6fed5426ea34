add_executable(vox2svo ${CMAKE_CURRENT_LIST_DIR}/vox2svo/main.c ${CMAKE_CURRENT_LIST_DIR}/vox2svo/demo.c)
target_link_libraries(vox2svo PRIVATE vx_tool_conv vx_tool)
if(TARGET vx_tool_mpi AND TARGET vx_conv_mesh)
  # mpirun -n N vox2svo MESH.glb OUT.svo: the mesh's regions over the ranks
  target_sources(vox2svo PRIVATE ${CMAKE_CURRENT_LIST_DIR}/vox2svo/mpi.c)
  target_link_libraries(vox2svo PRIVATE vx_tool_mpi vx_conv_mesh MPI::MPI_C)
  target_compile_definitions(vox2svo PRIVATE VX_HAVE_MPI=1)
endif()
