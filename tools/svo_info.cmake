add_executable(svo_info ${CMAKE_CURRENT_LIST_DIR}/svo_info/main.c)
# --to-glb and --to-vdb through the library's exports (convert/export.h),
# which say when this build lacks their writer
target_link_libraries(svo_info PRIVATE vx_convert vx_conv_export vx_tool_light vx_tool m)
