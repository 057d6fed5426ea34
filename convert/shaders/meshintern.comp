#version 450
/* convert/shaders/meshintern.comp - the cells' attribute tuples interned per
 * region for the octree builder (vx__svo_build_interned): the tuples are
 * radix-sorted (gpusort.comp) by (region, material, rgba) after a first
 * sort by normal when there are normals (LSD: the later sort is stable),
 * equal neighbours share an id, and each id's tuple is written once.
 *   MODE 0 (key): kv[j] = ((rgba, material | region << 16), cell); the cell
 *           is vals[j] when the normal sort ran (push perm), else j.
 *   MODE 3 (normal key): kv[j] = ((normal, 0), j).
 *   MODE 1 (flag): pos[j] = 1 where j starts a run of equal tuples.
 *   MODE 2 (out, after the flags' exclusive scan): ids[cell] = the run's
 *           index (global; runs are in region order), utab[run] = its tuple.
 * Ids are labels only: the builder's output depends on which cells share a
 * tuple, not on the numbering (svo/svo_internal.h). */
layout(local_size_x = 256) in;
layout(constant_id = 0) const uint MODE = 0;
layout(push_constant) uniform Push { uint n, attrs, perm; } pc; /* attrs: 1 rgba, 2 normal, 4 material */

layout(std430, binding = 0) buffer Keys { uvec2 keys[]; };
layout(std430, binding = 1) buffer Vals { uint vals[]; };
layout(std430, binding = 2) readonly buffer OKeys { uvec2 okeys[]; }; /* (local | brick << 18, brick >> 14) */
layout(std430, binding = 3) readonly buffer ORgba { uint orgba[]; };
layout(std430, binding = 4) readonly buffer ONrm { uint onrm[]; };
layout(std430, binding = 5) readonly buffer OMat { uint omat[]; };
layout(std430, binding = 6) readonly buffer Region { uint region[]; }; /* per brick index */
layout(std430, binding = 7) buffer Pos { uint pos[]; };
layout(std430, binding = 8) writeonly buffer Ids { uint ids[]; };
layout(std430, binding = 9) writeonly buffer UTab { uvec4 utab[]; }; /* rgba, normal, material, region */

uint rgba_of(uint c) { return (pc.attrs & 1u) != 0u ? orgba[c] : 0u; }
uint nrm_of(uint c) { return (pc.attrs & 2u) != 0u ? onrm[c] : 0u; }
uint mat_of(uint c) { return (pc.attrs & 4u) != 0u ? omat[c] & 0xFFFFu : 0u; }
uint region_of(uint c) { return region[(okeys[c].x >> 18) | (okeys[c].y << 14)]; }

bool head(uint j) {
    if (j == 0u) return true;
    if (keys[j] != keys[j - 1u]) return true;
    return (pc.attrs & 2u) != 0u && onrm[vals[j]] != onrm[vals[j - 1u]];
}

void main() {
    uint j = (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * 256u + gl_LocalInvocationID.x;
    if (j >= pc.n) return;
    if (MODE == 3u) {
        keys[j] = uvec2(onrm[j], 0u);
        vals[j] = j;
    } else if (MODE == 0u) {
        uint c = pc.perm != 0u ? vals[j] : j;
        keys[j] = uvec2(rgba_of(c), mat_of(c) | region_of(c) << 16);
        vals[j] = c;
    } else if (MODE == 1u) {
        pos[j] = head(j) ? 1u : 0u;
    } else {
        bool h = head(j);
        uint g = h ? pos[j] : pos[j] - 1u;
        uint c = vals[j];
        ids[c] = g;
        if (h) utab[g] = uvec4(rgba_of(c), nrm_of(c), mat_of(c), region_of(c));
    }
}
