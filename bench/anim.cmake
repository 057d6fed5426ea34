# Animation benchmark (issue 24): a generated smoke sequence through
# vx_conv_vdb_sequence against single frames; sizes of animations against
# their largest frame. Needs OpenVDB (it writes the frames itself).
if(TARGET vx_conv_vdb)
  add_executable(anim_bench ${CMAKE_CURRENT_SOURCE_DIR}/anim_bench.cpp)
  target_include_directories(anim_bench SYSTEM PRIVATE ${VX_OPENVDB_INCLUDE})
  target_link_libraries(anim_bench PRIVATE vx_conv_vdb)
endif()
