# A rank's driver narrowed to its GPU (tools/common/gpu_only.c, issue 23):
# the open family the tools export refuses the other GPU nodes, for the
# program's calls and a shared library's (zlib, through vx_svo) alike.
if(TARGET vx_tool_mpi_device)
  vx_add_test(test_gpu_only SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_gpu_only.c LIBS vx_tool_mpi_device vx_svo LABELS tools)
  target_include_directories(test_gpu_only PRIVATE ${CMAKE_SOURCE_DIR})
endif()
