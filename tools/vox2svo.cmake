add_executable(vox2svo ${CMAKE_CURRENT_LIST_DIR}/vox2svo/main.c ${CMAKE_CURRENT_LIST_DIR}/vox2svo/demo.c)
target_link_libraries(vox2svo PRIVATE vx_tool_conv vx_tool)
