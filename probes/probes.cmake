# probes/: light field probes (placement, CPU bake, .probes file, GI renderer).
if(VX_WITH_VULKAN)
  find_package(Threads REQUIRED)
  add_library(vx_probes STATIC
    ${CMAKE_CURRENT_LIST_DIR}/oct.c
    ${CMAKE_CURRENT_LIST_DIR}/light.c
    ${CMAKE_CURRENT_LIST_DIR}/bake.c
    ${CMAKE_CURRENT_LIST_DIR}/file.c
    ${CMAKE_CURRENT_LIST_DIR}/render_gi.c
    ${CMAKE_CURRENT_LIST_DIR}/lightfield.c
    ${CMAKE_CURRENT_LIST_DIR}/probe_gpu.c
    ${CMAKE_CURRENT_LIST_DIR}/gi_pass.c)
  target_link_libraries(vx_probes PUBLIC vx_render vx_svo Threads::Threads m)
endif()
