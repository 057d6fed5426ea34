# Animation benchmark (issue 24): a generated smoke sequence through
# vx_conv_vdb_sequence against single frames; sizes of animations against
# their largest frame. Needs OpenVDB (it writes the frames through the shim).
if(TARGET vx_conv_vdb)
  add_executable(anim_bench ${CMAKE_CURRENT_SOURCE_DIR}/anim_bench.c)
  target_link_libraries(anim_bench PRIVATE vx_conv_vdb m)
endif()
