add_library(vx_tool STATIC ${CMAKE_CURRENT_LIST_DIR}/common/tool.c)
target_link_libraries(vx_tool PUBLIC vx_core m)

# The --light syntax and light / sky descriptions (svo_render, svo_info, vox2svo).
add_library(vx_tool_light STATIC ${CMAKE_CURRENT_LIST_DIR}/common/light.c)
target_link_libraries(vx_tool_light PUBLIC vx_svo vx_tool)

# Converter options of the command line, shared by vox2svo and svo_view; the
# loading by extension is the library's (convert/file.h).
add_library(vx_tool_conv STATIC ${CMAKE_CURRENT_LIST_DIR}/common/conv.c)
target_link_libraries(vx_tool_conv PUBLIC vx_conv_file vx_tool)
if(TARGET vx_conv_vdb) # VDB sequences (smoke_####.vdb, a .txt list) are the tool's naming
  target_compile_definitions(vx_tool_conv PRIVATE VX_HAVE_VDB=1)
endif()

# A device opened on a thread of its own (svo_bake, svo_render under mpirun):
# the driver's start-up overlaps the tool's other start-up work.
if(TARGET vx_render)
  add_library(vx_tool_gpu STATIC ${CMAKE_CURRENT_LIST_DIR}/common/gpu_open.c)
  target_link_libraries(vx_tool_gpu PUBLIC vx_render vx_core)
endif()

# The MPI paths of svo_bake, svo_render and vox2svo (mpirun): launcher
# detection, ranks per host, ending the job (VX_WITH_MPI, where MPI is
# found); the device choice apart, for the Vulkan tools only.
if(VX_WITH_MPI AND MPI_C_FOUND)
  add_library(vx_tool_mpi STATIC ${CMAKE_CURRENT_LIST_DIR}/common/mpi.c)
  target_link_libraries(vx_tool_mpi PUBLIC vx_tool MPI::MPI_C)
  if(TARGET vx_render)
    add_library(vx_tool_mpi_device STATIC ${CMAKE_CURRENT_LIST_DIR}/common/mpi_device.c
                                          ${CMAKE_CURRENT_LIST_DIR}/common/gpu_only.c)
    target_link_libraries(vx_tool_mpi_device PUBLIC vx_tool_mpi vx_render)
    # gpu_only.c's open family must be what the Vulkan driver, loaded later
    # by dlopen, binds to: the executable exports them
    if(CMAKE_SYSTEM_NAME STREQUAL "Linux")
      foreach(f open open64 openat openat64 __open_2 __open64_2)
        target_link_options(vx_tool_mpi_device INTERFACE "LINKER:--export-dynamic-symbol=${f}")
      endforeach()
    endif()
  endif()
endif()
