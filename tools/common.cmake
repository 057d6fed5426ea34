add_library(vx_tool STATIC ${CMAKE_CURRENT_LIST_DIR}/common/tool.c)
target_link_libraries(vx_tool PUBLIC vx_core m)
