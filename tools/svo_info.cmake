add_executable(svo_info ${CMAKE_CURRENT_LIST_DIR}/svo_info/main.c)
target_link_libraries(svo_info PRIVATE vx_convert vx_tool)
