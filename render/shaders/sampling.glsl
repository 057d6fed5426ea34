// render/shaders/sampling.glsl - directions around a normal: one definition
// for the pass shaders (passes_common.glsl, cones/) and the path and photon
// tracers (probes/shaders/path_common.glsl). Include after defining PI.
// PT_PREC: `precise` in the GPU path tracer's render kernel (probes/shaders/
// probe.comp, PT_PRECISE), empty elsewhere.
#ifndef PT_PREC
#define PT_PREC
#endif

// An orthonormal basis t, bt around unit n (Duff et al.).
void basis(vec3 n, PT_PREC out vec3 t, PT_PREC out vec3 bt) {
    float sg = n.z < 0.0 ? -1.0 : 1.0;
    float a = -1.0 / (sg + n.z), b = n.x * n.y * a;
    t = vec3(1.0 + sg * n.x * n.x * a, sg * b, -sg * n.x);
    bt = vec3(b, sg + n.y * n.y * a, -n.y);
}

// Cosine-weighted direction around unit n.
PT_PREC vec3 cosine_dir(vec3 n, float u1, float u2) {
    vec3 t, bt;
    basis(n, t, bt);
    float r = sqrt(u1), phi = 2.0 * PI * u2;
    return normalize(r * cos(phi) * t + r * sin(phi) * bt + sqrt(max(0.0, 1.0 - u1)) * n);
}

// A direction uniform in the cone around unit n whose half angle has
// 1 - cos = omc (given as 1 - cos so that the sun's small cone keeps its
// precision; the sine from om (2 - om), not from 1 - z^2, for the same reason).
PT_PREC vec3 cone_dir(vec3 n, float omc, float u1, float u2) {
    vec3 t, bt;
    basis(n, t, bt);
    float om = u1 * omc, s = sqrt(max(0.0, om * (2.0 - om))), phi = 2.0 * PI * u2;
    return normalize(s * cos(phi) * t + s * sin(phi) * bt + (1.0 - om) * n);
}
