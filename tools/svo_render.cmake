# svo_render: render a .svo scene to PNG/EXR with the Vulkan tracer (or --cpu);
# with MPI (where found) also mpirun -n N svo_render --mode pathtrace.
if(VX_WITH_VULKAN AND TARGET vx_image)
  add_executable(svo_render ${CMAKE_CURRENT_SOURCE_DIR}/svo_render/main.c)
  target_link_libraries(svo_render PRIVATE vx_photons vx_cones vx_probes vx_render vx_image vx_tool_light vx_tool vx_svo)
  if(TARGET vx_tool_mpi_device)
    # mpirun -n N svo_render --mode pathtrace: rows over the ranks
    target_sources(svo_render PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/svo_render/mpi.c)
    target_link_libraries(svo_render PRIVATE vx_tool_mpi_device vx_tool_gpu MPI::MPI_C)
    target_compile_definitions(svo_render PRIVATE VX_HAVE_MPI=1)
  endif()
endif()
