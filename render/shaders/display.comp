// render/shaders/display.comp - the tracer's float image to display bytes on
// the GPU (render/display.h): each pixel's R, G, B clamped to [0,1] and
// rounded to 8 bits exactly as svo_view's host conversion (lrintf(v * 255):
// round half to even), in R,G,B,A or B,G,R,A byte order, then an overlay of
// premultiplied 8-bit colour and coverage laid over it:
// out = P + F * (255 - A) / 255, rounded.
#version 450
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 256) in;
layout(std430, set = 0, binding = 0) readonly buffer Src { vec4 src[]; };
layout(std430, set = 0, binding = 1) readonly buffer Ovl { uint ovl[]; };
#ifdef TO_IMAGE
// the image shown itself (a storage image without a format: B,G,R,A ones
// have no GLSL format qualifier), instead of a buffer copied to it
layout(set = 0, binding = 2) uniform writeonly image2D dsti;
#else
layout(std430, set = 0, binding = 2) writeonly buffer Dst { uint dst[]; };
#endif
layout(push_constant) uniform Push {
    uint n;       // pixels
    uint bgra;    // 1: B,G,R,A bytes (the overlay's order; and the buffer's)
    uint overlay; // 1: lay ovl over the frame
    uint row;     // groups per dispatch row (2D dispatch of large frames)
    uint width;   // frame width (TO_IMAGE: pixel i at (i % width, i / width))
    uint iw, ih;  // TO_IMAGE: the image's size (pixels outside it are not stored)
} pc;

#include "display_out.glsl"

void main() {
    uint i = (gl_WorkGroupID.y * pc.row + gl_WorkGroupID.x) * 256u + gl_LocalInvocationID.x;
    if (i >= pc.n) return;
    uvec3 rgb = display_rgb(src[i], pc.overlay != 0u ? ovl[i] : 0u, pc.bgra != 0u, pc.overlay != 0u);
#ifdef TO_IMAGE
    // the image's format puts the channels in its byte order: store R, G, B;
    // k / 255 converts back to exactly k (round to nearest of k +- 1 ulp)
    uint x = i % pc.width, y = i / pc.width;
    if (x < pc.iw && y < pc.ih) imageStore(dsti, ivec2(x, y), vec4(vec3(rgb) / 255.0, 1.0));
#else
    uvec3 c = pc.bgra != 0u ? rgb.zyx : rgb; // the buffer's bytes in the display's order
    dst[i] = c.x | (c.y << 8) | (c.z << 16) | (255u << 24);
#endif
}
