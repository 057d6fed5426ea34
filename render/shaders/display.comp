// render/shaders/display.comp - the tracer's float image to display bytes on
// the GPU (render/display.h): each pixel's R, G, B clamped to [0,1] and
// rounded to 8 bits exactly as svo_view's host conversion (lrintf(v * 255):
// round half to even), in R,G,B,A or B,G,R,A byte order, then an overlay of
// premultiplied 8-bit colour and coverage laid over it:
// out = P + F * (255 - A) / 255, rounded.
#version 450
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

uint to8(float v) { return uint(roundEven(clamp(v, 0.0, 1.0) * 255.0)); }

void main() {
    uint i = (gl_WorkGroupID.y * pc.row + gl_WorkGroupID.x) * 256u + gl_LocalInvocationID.x;
    if (i >= pc.n) return;
    vec4 s = src[i];
    uint r = to8(s.r), g = to8(s.g), b = to8(s.b);
    uvec3 c = pc.bgra != 0u ? uvec3(b, g, r) : uvec3(r, g, b);
    if (pc.overlay != 0u) {
        uint o = ovl[i], a = o >> 24;
        if (a != 0u) {
            uvec3 p = uvec3(o & 255u, (o >> 8) & 255u, (o >> 16) & 255u);
            c = min(p + (c * (255u - a) + 127u) / 255u, uvec3(255u));
        }
    }
#ifdef TO_IMAGE
    // the image's format puts the channels in its byte order: store R, G, B;
    // k / 255 converts back to exactly k (round to nearest of k +- 1 ulp)
    uvec3 rgb = pc.bgra != 0u ? c.zyx : c;
    uint x = i % pc.width, y = i / pc.width;
    if (x < pc.iw && y < pc.ih) imageStore(dsti, ivec2(x, y), vec4(vec3(rgb) / 255.0, 1.0));
#else
    dst[i] = c.x | (c.y << 8) | (c.z << 16) | (255u << 24);
#endif
}
