// render/shaders/screen_cull.glsl - the screen cull's miss pass (issue 21's
// twelfth sitting), shared by trace.comp and trace_compact.comp: the host
// traces only the pixels [R.x, R.z) x [R.y, R.w) whose rays can meet the
// scene's box (vx__frame_rect) and runs a second dispatch, one invocation per
// pixel outside that rectangle, that writes their misses without a ray.

// The pixel of miss-pass invocation i (64 a workgroup, the groups in x then
// y): the pixels outside the rectangle numbered row by row, the rows above
// it, the rows below it, then the rows beside it (left and right parts).
// False past the last of them.
bool cull_miss_pixel(uvec4 R, uint W, uint H, out uvec2 px) {
    uint i = (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * 64u + gl_LocalInvocationIndex;
    uint above = R.y * W, below = (H - R.w) * W, side = W - (R.z - R.x);
    px = uvec2(0u);
    if (i < above) px = uvec2(i % W, i / W);
    else if (i - above < below) px = uvec2((i - above) % W, R.w + (i - above) / W);
    else {
        i -= above + below;
        if (side == 0u || i >= side * (R.w - R.y)) return false;
        uint c = i % side;
        px = uvec2(c < R.x ? c : R.z + c - R.x, R.y + i / side);
    }
    return true;
}
