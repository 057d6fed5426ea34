# svo_bake: bake light field probes for a .svo scene (CPU or GPU), shards and
# merge; with MPI (VX_WITH_MPI, where found) also mpirun -n N svo_bake.
# OpenImageIO only for --exr: a GPU machine without it still bakes.
if(VX_WITH_VULKAN)
  add_executable(svo_bake ${CMAKE_CURRENT_LIST_DIR}/svo_bake/main.c)
  target_link_libraries(svo_bake PRIVATE vx_probes vx_tool vx_tool_gpu vx_svo)
  if(VX_WITH_OIIO)
    target_link_libraries(svo_bake PRIVATE vx_image)
    target_compile_definitions(svo_bake PRIVATE VX_HAVE_IMAGE=1)
  endif()
  if(VX_WITH_MPI AND MPI_C_FOUND)
    target_sources(svo_bake PRIVATE ${CMAKE_CURRENT_LIST_DIR}/svo_bake/mpi.c)
    target_link_libraries(svo_bake PRIVATE vx_tool_mpi_device MPI::MPI_C)
    target_compile_definitions(svo_bake PRIVATE VX_HAVE_MPI=1)
  endif()
endif()
