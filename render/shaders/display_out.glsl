// render/shaders/display_out.glsl - display bytes from a frame's colour
// (render/display.h): R, G, B clamped to [0,1] and rounded to 8 bits as
// lrintf(v * 255) (round half to even: svo_view's host conversion, the PNG's
// bytes), then an overlay of premultiplied 8-bit colour and coverage in the
// display's byte order laid over them: out = P + F * (255 - A) / 255, rounded.
// display.comp converts an image with it; with DISPLAY_OUT the frame's last
// pass (frame.comp, resolve.comp, post.comp, render/pipeline.c) stores its
// colour this way into the image shown, so no conversion pass reads the
// frame again.

uint display_to8(float v) { return uint(roundEven(clamp(v, 0.0, 1.0) * 255.0)); }

// The pixel's display colour in R, G, B order (bgra: the overlay's bytes are
// B, G, R, A).
uvec3 display_rgb(vec4 s, uint o, bool bgra, bool overlay) {
    uint r = display_to8(s.r), g = display_to8(s.g), b = display_to8(s.b);
    uvec3 c = bgra ? uvec3(b, g, r) : uvec3(r, g, b);
    if (overlay) {
        uint a = o >> 24;
        if (a != 0u) {
            uvec3 p = uvec3(o & 255u, (o >> 8) & 255u, (o >> 16) & 255u);
            c = min(p + (c * (255u - a) + 127u) / 255u, uvec3(255u));
        }
    }
    return bgra ? c.zyx : c;
}

#ifdef DISPLAY_OUT
// The frame's last pass writes the image shown (a storage image without a
// format: B,G,R,A ones have no GLSL format qualifier) through PC.u3: x 1 for
// B,G,R,A overlay bytes, y 1 to lay the overlay (binding 25) over the frame,
// zw the image's size (pixels outside it are not stored). Bindings 25 and 26
// follow the passes' 0-24 (render/pipeline.c NBIND).
layout(std430, binding = 25) readonly buffer DisplayOvl { uint display_ovl[]; };
layout(binding = 26) uniform writeonly image2D display_img;

void display_store(uvec2 px, uint i, vec4 c) {
    if (px.x >= PC.u3.z || px.y >= PC.u3.w) return;
    uint o = PC.u3.y != 0u ? display_ovl[i] : 0u;
    // the image's format puts the channels in its byte order: store R, G, B;
    // k / 255 converts back to exactly k (round to nearest of k +- 1 ulp)
    imageStore(display_img, ivec2(px), vec4(vec3(display_rgb(c, o, PC.u3.x != 0u, PC.u3.y != 0u)) / 255.0, 1.0));
}
#endif
