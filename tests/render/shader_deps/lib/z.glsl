// included by a.comp through vx_spirv_header's INCLUDES
float z_val() { return 3.0; }
