# Greedy meshing of whole scenes (formats/voxmesh.h; issue 19's goal).
add_executable(voxmesh_bench ${CMAKE_CURRENT_LIST_DIR}/voxmesh_bench.c)
target_link_libraries(voxmesh_bench PRIVATE vx_voxmesh vx_svo)
