# A compute kernel's spec in the shader lists of render/render.cmake and
# probes/probes.cmake: NAME:FILE[:DEFINE] -> the embedded kernel's name, its
# source FILE.comp and the glslangValidator define (-DDEFINE, or empty).
function(vx_shader_spec spec name_var file_var defs_var)
  string(REPLACE ":" ";" parts ${spec})
  list(GET parts 0 name)
  list(GET parts 1 file)
  set(defs)
  list(LENGTH parts nparts)
  if(nparts GREATER 2)
    list(GET parts 2 def)
    set(defs -D${def})
  endif()
  set(${name_var} ${name} PARENT_SCOPE)
  set(${file_var} ${file} PARENT_SCOPE)
  set(${defs_var} ${defs} PARENT_SCOPE)
endfunction()
