// render/shaders/entry_tau.glsl - the exact hit distance of deep models, one
// definition for the two float walks: trace_common.glsl's (trace.comp, the
// passes, probes, cones, photons) and trace_compact.comp's (the compact
// layout, which does not include trace_common.glsl). Each includes it where
// its own copy stood, so every kernel's SPIR-V is byte for byte what its copy
// compiled to.
//
// Exact models (Model and CModel flag 2): the ray's distance from the model
// box's entry point oa (+ its rounding error oa_lo) to the entry of the box
// [lo, lo + sz] (model units, exact integers), the largest crossing of its
// entry planes, at least 0. The differences to the planes are exact or
// nearly (Sterbenz), so t is right to float rounding where the walk's
// crossing times pos * coef - bias lose 2^(depth - 23) of a cell to
// cancellation (the strict rule's depth errors, issue 18).
float entry_tau(vec3 oa, vec3 oa_lo, vec3 d, vec3 lo, float sz) {
    // precise in every kernel (NoContraction also forbids reassociation): a
    // driver may otherwise apply exact algebra, as the NVIDIA compiler did to
    // the instance two-sum (test_spirv_precise), and (pl - oa) - oa_lo as
    // pl - (oa + oa_lo) rounds to pl - oa, losing the low part the hi/lo
    // origin exists for; test_spirv_precise checks all 6 operations
    precise vec3 pl = vec3(d.x < 0.0 ? lo.x + sz : lo.x, d.y < 0.0 ? lo.y + sz : lo.y, d.z < 0.0 ? lo.z + sz : lo.z);
    precise vec3 tau = ((pl - oa) - oa_lo) / d;
    float r = 0.0;
    if (d.x != 0.0) r = max(r, tau.x);
    if (d.y != 0.0) r = max(r, tau.y);
    if (d.z != 0.0) r = max(r, tau.z);
    return r;
}
