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
layout(std430, set = 0, binding = 2) writeonly buffer Dst { uint dst[]; };
layout(push_constant) uniform Push {
    uint n;       // pixels
    uint bgra;    // 1: B,G,R,A bytes
    uint overlay; // 1: lay ovl over the frame
    uint row;     // groups per dispatch row (2D dispatch of large frames)
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
    dst[i] = c.x | (c.y << 8) | (c.z << 16) | (255u << 24);
}
