// render/shaders/dielectric.glsl - a dielectric interface, shared by the path
// tracer (probes/shaders/path_common.glsl dielectric, glass_walk) and the pass
// pipeline's glass seen directly (pass_bodies.glsl glass_pixel), so that both
// weigh reflection and refraction with the same Fresnel term (probes/pathtrace.c
// fresnel_dielectric is its double twin).
// PT_PREC: `precise` where the includer defines it so (path_common.glsl), else nothing.
#ifndef PT_PREC
#define PT_PREC
#endif

// Unpolarised Fresnel reflectance; cosi > 0 on the incident side, eta = n_transmitted / n_incident.
PT_PREC float fresnel_dielectric(float cosi, float eta) {
    PT_PREC float s2t = (1.0 - cosi * cosi) / (eta * eta);
    if (s2t >= 1.0) return 1.0;
    float ct = sqrt(1.0 - s2t);
    float rs = (cosi - eta * ct) / (cosi + eta * ct), rp = (eta * cosi - ct) / (eta * cosi + ct);
    return 0.5 * (rs * rs + rp * rp);
}
