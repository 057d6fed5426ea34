/* tools/svo_view/settings.h - the render panel's GI settings and the
 * properties panel's material fields as text options, parsed in one place
 * for the panels and the script commands (`gi OPTION VALUE`, `material ID
 * FIELD VALUE`).
 *
 * The GI options are svo_render's, named without the "--" and with its
 * ranges, so a frame of svo_view with `gi cone-res 64` equals svo_render
 * ... --cone-res 64 of the saved scene (tests/view). Zero fields are the
 * defaults of the desc they belong to (cones.h, photons.h, render/pipeline.h),
 * as in svo_render. */
#ifndef VX_SVO_VIEW_SETTINGS_H
#define VX_SVO_VIEW_SETTINGS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "cones/cones.h"
#include "photons/photons.h"

typedef struct sv_gi_settings {
    vx_cone_desc cone;     /* gi=cones: cone-res, cones, cone-aperture, cone-bounces, cone-sun-angle, and the
                            * switches cone-isotropic, cone-ao, cone-half, cone-shadows, cone-no-specular */
    vx_photon_desc photon; /* gi=photons: photons, radius, final-gather */
    uint32_t bounces;      /* gi=pathtrace: bounces (0: the default) */
    uint32_t seed;         /* seed (gi=pathtrace, gi=photons and the pipeline's samples) */
    uint32_t spp;          /* spp, also passes-count (gi=photons: a pass a sample); 0: the pipeline's default */
    uint32_t ao_rays;      /* ao-rays (0: 4) */
    double ao_radius;      /* ao-radius, world units (0: 4 cells) */
} sv_gi_settings;

/* Option `name` (as svo_render's without "--"; switches take on|off) set
 * from `value`; false with the reason in why (g unchanged). */
bool sv_gi_option(sv_gi_settings* g, const char* name, const char* value, char* why, size_t why_size);
/* The settings as svo_render options ("--cone-res 64 --cone-shadows"), only
 * those that differ from zero; returns the length (cut to out_size - 1). */
size_t sv_gi_options_format(const sv_gi_settings* g, char* out, size_t out_size);

/* A material field as dictionary pairs (docs/FORMAT.md 4.1): type
 * diffuse|metal|glass|emit (_type), rough (_rough), metal (_metal), spec
 * (_spec), trans (_trans) in [0,1], ior in [1,4] (_ri, the index, and
 * _ior, MagicaVoxel's index - 1, so both readers agree), emit >= 0 (_emit),
 * flux in [0,16] (_flux), emit_color R,G,B each in [0,1e30] or none
 * (_emit_color, voxkit's key: the emission's own colour; none = 0 0 0, the
 * voxel's colour). *n pairs (1 or 2) in keys/values; false with the reason
 * in why. */
#define SV_MATERIAL_VALUE 64 /* bytes of one value */
bool sv_material_field(const char* field, const char* value, const char* keys[2], char values[2][SV_MATERIAL_VALUE],
                       uint32_t* n, char* why, size_t why_size);

#endif
