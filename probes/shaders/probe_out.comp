#version 450
// probes/shaders/probe_out.comp - the probe renderer's result into another
// module's image on the GPU (the pass pipeline's gi buffer): pixel i of the
// renderer's accumulation (probe.comp: flags at 0, then per pixel the running
// sum and the samples done) divided by the sample count, as the host path
// divides it after a readback.
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Src { vec4 src[]; };
layout(std430, binding = 1) writeonly buffer Dst { vec4 dst[]; };
layout(push_constant) uniform Push { uint npx, spp, row; } PC;

void main() {
    uint i = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * PC.row;
    if (i >= PC.npx) return;
    dst[i] = src[2u * i + 1u] / float(PC.spp);
}
