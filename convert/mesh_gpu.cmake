# The mesh voxelizer on the GPU (convert/mesh_gpu.h): library vx_conv_mesh_gpu
# over vx_render's device layer (render/ comes later in the tree: the target
# is named here and resolved when the build is generated).
if(TARGET vx_conv_mesh AND VX_WITH_VULKAN)
  set(VX_MESHGPU_SPV_DIR ${CMAKE_CURRENT_BINARY_DIR}/spv)
  file(MAKE_DIRECTORY ${VX_MESHGPU_SPV_DIR})
  set(VX_MESHGPU_SPV)
  foreach(name meshvox meshreduce gpusort gpuscan meshintern meshbuild)
    vx_spirv_header(${VX_MESHGPU_SPV_DIR}/${name}.comp.h ${CMAKE_CURRENT_LIST_DIR}/shaders/${name}.comp vx__${name}_spv_arr)
    list(APPEND VX_MESHGPU_SPV ${VX_MESHGPU_SPV_DIR}/${name}.comp.h)
  endforeach()
  add_library(vx_conv_mesh_gpu STATIC ${CMAKE_CURRENT_LIST_DIR}/mesh_gpu.c ${VX_MESHGPU_SPV})
  target_include_directories(vx_conv_mesh_gpu PRIVATE ${VX_MESHGPU_SPV_DIR})
  target_link_libraries(vx_conv_mesh_gpu PUBLIC vx_conv_mesh vx_render Threads::Threads)
endif()
