/* tests/svo/test_svo_light.c - lights and materials as scene data:
 * vx_light_validate, vx_sky_validate and the typed reading of MagicaVoxel
 * MATL dictionaries (vx_svo_material_resolve), each value checked against
 * the rule of svo.h computed here by hand. */
#include <math.h>

#include "svo/svo.h"
#include "tests/test.h"

static const double PI = 3.14159265358979323846;

/* A material whose dictionary holds the NULL-terminated key/value list. */
static vx_svo_material mat(uint32_t id, const char* const* kv, char* store, size_t cap) {
    size_t n = 0;
    for (int i = 0; kv[i]; i++) {
        size_t l = strlen(kv[i]) + 1;
        if (n + l > cap) break;
        memcpy(store + n, kv[i], l);
        n += l;
    }
    return (vx_svo_material){.id = id, .dict_size = (uint32_t)n, .dict = n ? store : NULL};
}

static vx_material resolve(const char* const* kv) {
    char buf[512];
    vx_svo_material m = mat(1, kv, buf, sizeof buf);
    return vx_svo_material_resolve(&m);
}

static bool near(double a, double b) { return fabs(a - b) <= 1e-12 * fmax(1, fabs(b)); }

static void test_material_defaults(void) {
    vx_material d = vx_svo_material_resolve(NULL);
    CHECK(d.type == VX_MATERIAL_DIFFUSE && d.roughness == 1 && d.metalness == 0 && d.emission == 0 && d.transmission == 0);
    vx_material e = resolve((const char* const[]){NULL}); /* an empty dictionary */
    CHECK(d.type == e.type && d.roughness == e.roughness && d.metalness == e.metalness && d.specular == e.specular &&
          d.ior == e.ior && d.transmission == e.transmission && d.emission == e.emission);
    vx_material m = resolve((const char* const[]){"_type", "_metal", NULL});
    CHECK(m.type == VX_MATERIAL_METAL && m.metalness == 1 && m.roughness == 0.1 && m.specular == 0.5);
    vx_material g = resolve((const char* const[]){"_type", "_glass", NULL});
    CHECK(g.type == VX_MATERIAL_GLASS && g.transmission == 1 && g.ior == 1.5 && g.roughness == 0.1);
    /* unknown and blend/media types read as diffuse */
    CHECK(resolve((const char* const[]){"_type", "_blend", NULL}).type == VX_MATERIAL_DIFFUSE);
    CHECK(resolve((const char* const[]){"_type", "_media", NULL}).type == VX_MATERIAL_DIFFUSE);
    CHECK(resolve((const char* const[]){"_type", "plastic", NULL}).type == VX_MATERIAL_DIFFUSE);
}

/* MagicaVoxel stores the index of refraction minus one in _ior; _ri, when
 * present and usable, is the index itself. */
static void test_material_ior(void) {
    vx_material g = resolve((const char* const[]){"_type", "_glass", "_ior", "0.3", NULL});
    CHECK(near(g.ior, 1.3));
    g = resolve((const char* const[]){"_type", "_glass", "_ior", "0.3", "_ri", "1.7", NULL});
    CHECK(near(g.ior, 1.7));
    g = resolve((const char* const[]){"_type", "_glass", "_ior", "0.3", "_ri", "nan", NULL});
    CHECK(near(g.ior, 1.3)); /* an unusable _ri falls back to _ior */
    g = resolve((const char* const[]){"_type", "_glass", "_ior", "9", NULL});
    CHECK(g.ior == 4); /* clamped to 1 + 3 */
    g = resolve((const char* const[]){"_type", "_glass", "_ior", "-0.5", NULL});
    CHECK(g.ior == 1); /* below 0 clamps to an index of 1 */
    g = resolve((const char* const[]){"_type", "_glass", "_ri", "0.5", NULL});
    CHECK(g.ior == 1);
}

static void test_material_clamp_and_nan(void) {
    vx_material m = resolve((const char* const[]){"_type", "_metal", "_rough", "2", "_metal", "-1", "_spec", "7", NULL});
    CHECK(m.roughness == 1 && m.metalness == 0 && m.specular == 1);
    static const char* const bad[] = {"nan", "NaN", "inf", "-inf", "1e400", "abc", "", " "};
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
        vx_material r = resolve((const char* const[]){"_type", "_metal", "_rough", bad[i], "_trans", bad[i], NULL});
        CHECKF(r.roughness == 0.1 && r.transmission == 0 && isfinite(r.ior), "'%s'", bad[i]);
        vx_material e = resolve((const char* const[]){"_type", "_emit", "_emit", bad[i], "_flux", bad[i], NULL});
        CHECKF(e.emission == 0 && e.type == VX_MATERIAL_DIFFUSE, "'%s'", bad[i]); /* _emit without emission */
    }
    m = resolve((const char* const[]){"_type", "_metal", "_rough", "0.25x", NULL}); /* a number prefix counts */
    CHECK(m.roughness == 0.25);
}

static void test_material_emission(void) {
    vx_material e = resolve((const char* const[]){"_type", "_emit", "_emit", "2", "_flux", "3", NULL});
    CHECK(e.type == VX_MATERIAL_EMIT && e.emission == 16); /* 2 * 2^3 */
    e = resolve((const char* const[]){"_type", "_emit", "_emit", "0.5", "_flux", "100", NULL});
    CHECK(e.emission == 0.5 * 65536); /* _flux clamps to 16 */
    e = resolve((const char* const[]){"_type", "_emit", "_emit", "0", NULL});
    CHECK(e.type == VX_MATERIAL_DIFFUSE && e.emission == 0);
    e = resolve((const char* const[]){"_type", "_metal", "_emit", "1.5", NULL}); /* any type may emit */
    CHECK(e.type == VX_MATERIAL_METAL && e.emission == 1.5);
    e = resolve((const char* const[]){"_type", "_emit", "_emit", "-3", NULL});
    CHECK(e.emission == 0);
}

/* voxkit's _emit_color: the emitted light's own colour in place of the voxel's (glTF's emissiveFactor),
 * three finite numbers >= 0; anything else leaves the voxel's colour. vx_material_emitted and its GPU terms
 * give the same radiance. */
static void test_material_emission_color(void) {
    vx_material e = resolve((const char* const[]){"_type", "_emit", "_emit", "2", "_emit_color", "1 0.25 0", NULL});
    CHECK(e.emission == 2 && e.emission_color[0] == 1 && e.emission_color[1] == 0.25 && e.emission_color[2] == 0);
    static const char* const bad[] = {"1 2", "1 nan 0", "-1 0 0", "1 2 3 4", "abc", "", "1,0,0", "inf 0 0"};
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
        vx_material b = resolve((const char* const[]){"_type", "_emit", "_emit", "2", "_emit_color", bad[i], NULL});
        CHECKF(b.emission == 2 && b.emission_color[0] == 0 && b.emission_color[1] == 0 && b.emission_color[2] == 0,
               "'%s'", bad[i]);
    }
    e = resolve((const char* const[]){"_type", "_emit", "_emit", "2", "_emit_color", " 0.5 1e40 3 ", NULL});
    CHECK(e.emission_color[0] == 0.5 && e.emission_color[1] == 1e30 && e.emission_color[2] == 3); /* clamped */
    /* the radiance: own colour x emission, or the voxel's colour x emission; the terms give the same */
    const double rgb[3] = {0.2, 0.4, 0.8};
    vx_material own = resolve((const char* const[]){"_type", "_emit", "_emit", "2", "_emit_color", "1 0.25 0", NULL});
    vx_material plain = resolve((const char* const[]){"_type", "_emit", "_emit", "2", NULL});
    vx_material none = resolve((const char* const[]){"_type", "_metal", "_emit_color", "1 1 1", NULL});
    const vx_material* ms[3] = {&own, &plain, &none};
    const double want[3][3] = {{2, 0.5, 0}, {0.4, 0.8, 1.6}, {0, 0, 0}};
    for (int i = 0; i < 3; i++) {
        double out[3];
        float k[4];
        vx_material_emitted(ms[i], rgb, out);
        vx_material_emitted_terms(ms[i], k);
        for (int c = 0; c < 3; c++) {
            CHECKF(near(out[c], want[i][c]), "material %d channel %d: %g, want %g", i, c, out[c], want[i][c]);
            CHECKF(fabs(rgb[c] * k[3] + k[c] - want[i][c]) <= 1e-6, "terms %d channel %d", i, c);
        }
    }
    float k[4];
    vx_material_emitted_terms(NULL, k);
    CHECK(k[0] == 0 && k[1] == 0 && k[2] == 0 && k[3] == 0);
}

static void test_scene_material(void) {
    char b1[128], b2[128];
    vx_svo_material ms[2] = {mat(7, (const char* const[]){"_type", "_metal", "_rough", "0.5", NULL}, b1, sizeof b1),
                             mat(9, (const char* const[]){"_type", "_glass", NULL}, b2, sizeof b2)};
    vx_svo_scene s;
    vx_svo_scene_init(&s, NULL);
    s.materials = ms;
    s.material_count = 2;
    CHECK(vx_svo_scene_material(&s, 7).type == VX_MATERIAL_METAL && vx_svo_scene_material(&s, 7).roughness == 0.5);
    CHECK(vx_svo_scene_material(&s, 9).type == VX_MATERIAL_GLASS);
    CHECK(vx_svo_scene_material(&s, 8).type == VX_MATERIAL_DIFFUSE);
    CHECK(vx_svo_scene_material(NULL, 7).type == VX_MATERIAL_DIFFUSE);
}

static void test_light_validate(void) {
    vx_error e;
    vx_light ok[5] = {
        {.type = VX_LIGHT_DIRECTIONAL, .direction = {0, 0, 1}, .color = {1, 1, 1}, .intensity = 1},
        {.type = VX_LIGHT_POINT, .color = {1, 1, 1}, .intensity = 1},
        {.type = VX_LIGHT_SPOT, .direction = {0, 0, -1}, .color = {1, 1, 1}, .intensity = 1, .outer_cone = 1.5707963267948966},
        {.type = VX_LIGHT_SPHERE, .color = {1, 1, 1}, .intensity = 1, .radius = 1},
        {.type = VX_LIGHT_RECT, .direction = {0, 0, -1}, .tangent = {1, 1, 0}, .color = {1, 1, 1}, .intensity = 1, .size = {1, 1}},
    };
    for (uint32_t i = 0; i < 5; i++) CHECKF(vx_light_validate(&ok[i], i, &e) == VX_OK, "%u: %s", i, e.msg);
    vx_light l = ok[2];
    l.position[1] = NAN;
    CHECK(vx_light_validate(&l, 12, &e) != VX_OK && strstr(e.msg, "light 12"));
    l = ok[2], l.intensity = -1;
    CHECK(vx_light_validate(&l, 3, &e) != VX_OK && strstr(e.msg, "light 3: negative intensity"));
    l = ok[2], l.inner_cone = 0.5, l.outer_cone = 0.4;
    CHECK(vx_light_validate(&l, 0, &e) != VX_OK && strstr(e.msg, "cone"));
    l = ok[2], l.direction[2] = 0;
    CHECK(vx_light_validate(&l, 0, &e) != VX_OK && strstr(e.msg, "direction"));
    l = ok[4], l.tangent[0] = 0, l.tangent[1] = 0, l.tangent[2] = 2; /* parallel to the normal */
    CHECK(vx_light_validate(&l, 0, &e) != VX_OK && strstr(e.msg, "tangent"));
    l = ok[1], l.type = (vx_light_type)9;
    CHECK(vx_light_validate(&l, 0, &e) != VX_OK && strstr(e.msg, "unknown type"));
    l = ok[1], l.flags = 2;
    CHECK(vx_light_validate(&l, 0, &e) != VX_OK && strstr(e.msg, "flags"));
    l = ok[1], l.flags = VX_LIGHT_FROM_VOXELS; /* a valid light of the renderer, not of a file */
    CHECK(vx_light_validate(&l, 0, &e) == VX_OK);
    l = ok[0], l.angular_diameter = 4;
    CHECK(vx_light_validate(&l, 0, &e) != VX_OK);
}

static void test_sky_validate(void) {
    vx_error e;
    vx_sky k = {0};
    CHECK(vx_sky_validate(&k, &e) == VX_OK);
    k = (vx_sky){.type = VX_SKY_GRADIENT, .color = {1, 1, 1}, .horizon = {1, 1, 1}, .ground = {0.2, 0.2, 0.2}};
    CHECK(vx_sky_validate(&k, &e) == VX_OK);
    k.ground[1] = -1;
    CHECK(vx_sky_validate(&k, &e) != VX_OK && strstr(e.msg, "colour"));
    k = (vx_sky){.type = VX_SKY_CONSTANT, .color = {1, 1, 1}, .ground = {1, 0, 0}};
    CHECK(vx_sky_validate(&k, &e) != VX_OK && strstr(e.msg, "does not use"));
    k = (vx_sky){.type = VX_SKY_ENVMAP, .intensity = 1};
    CHECK(vx_sky_validate(&k, &e) != VX_OK && strstr(e.msg, "path"));
    snprintf(k.path, sizeof k.path, "sky.hdr");
    CHECK(vx_sky_validate(&k, &e) == VX_OK);
    k.rotation = NAN;
    CHECK(vx_sky_validate(&k, &e) != VX_OK);
    k = (vx_sky){.type = VX_SKY_CONSTANT, .color = {1, 1, 1}, .path = "x"};
    CHECK(vx_sky_validate(&k, &e) != VX_OK && strstr(e.msg, "path"));
    k.type = (vx_sky_type)7;
    CHECK(vx_sky_validate(&k, &e) != VX_OK && strstr(e.msg, "unknown type"));
}

/* The map's file: relative paths are beside the .svo, absolute ones stay. */
static void test_sky_path(void) {
    vx_sky k = {.type = VX_SKY_ENVMAP, .intensity = 1, .path = "maps/sky.exr"};
    char out[64];
    CHECK(vx_sky_path(&k, "/data/scenes/a.svo", out, sizeof out) && !strcmp(out, "/data/scenes/maps/sky.exr"));
    CHECK(vx_sky_path(&k, "a.svo", out, sizeof out) && !strcmp(out, "maps/sky.exr"));
    CHECK(vx_sky_path(&k, NULL, out, sizeof out) && !strcmp(out, "maps/sky.exr"));
    CHECK(!vx_sky_path(&k, "/data/scenes/a.svo", out, 20) && out[0] == 0); /* does not fit */
    snprintf(k.path, sizeof k.path, "/abs/sky.hdr");
    CHECK(vx_sky_path(&k, "/data/a.svo", out, sizeof out) && !strcmp(out, "/abs/sky.hdr"));
    k = (vx_sky){.type = VX_SKY_CONSTANT, .color = {1, 1, 1}};
    CHECK(!vx_sky_path(&k, "/data/a.svo", out, sizeof out) && out[0] == 0);
}

/* The sky as text (vx_sky_parse, vx_sky_format): each form parsed to the
 * record written by hand, written back as the shortest text that parses to
 * the same bytes; malformed and invalid texts refused with what was wrong. */
static void test_sky_text(void) {
    vx_error e = {0};
    vx_sky k, b;
    char t[VX_SKY_SPEC_MAX];
    CHECK(vx_sky_parse("default", &k, &e) == VX_OK && k.type == VX_SKY_DEFAULT);
    CHECK(vx_sky_format(&k, t, sizeof t, &e) == VX_OK && !strcmp(t, "default"));
    CHECK(vx_sky_parse("0.2,0.3,1e3", &k, &e) == VX_OK && k.type == VX_SKY_CONSTANT && k.color[0] == 0.2 &&
          k.color[1] == 0.3 && k.color[2] == 1000);
    CHECK(vx_sky_format(&k, t, sizeof t, &e) == VX_OK && !strcmp(t, "0.2,0.3,1000"));
    CHECK(vx_sky_parse("gradient:0.2,0.3,0.6:0.7,0.7,0.8:0.1,0.1,0", &k, &e) == VX_OK && k.type == VX_SKY_GRADIENT &&
          k.horizon[2] == 0.8 && k.ground[2] == 0);
    CHECK(vx_sky_format(&k, t, sizeof t, &e) == VX_OK && !strcmp(t, "gradient:0.2,0.3,0.6:0.7,0.7,0.8:0.1,0.1,0"));
    CHECK(vx_sky_parse("map:env/sky.exr", &k, &e) == VX_OK && k.type == VX_SKY_ENVMAP && k.intensity == 1 &&
          k.rotation == 0 && !strcmp(k.path, "env/sky.exr"));
    CHECK(vx_sky_format(&k, t, sizeof t, &e) == VX_OK && !strcmp(t, "map:env/sky.exr"));
    CHECK(vx_sky_parse("map:sky.hdr:2.5", &k, &e) == VX_OK && k.intensity == 2.5);
    CHECK(vx_sky_format(&k, t, sizeof t, &e) == VX_OK && !strcmp(t, "map:sky.hdr:2.5"));
    CHECK(vx_sky_parse("map:/abs/sky.hdr:1:90", &k, &e) == VX_OK && near(k.rotation, PI / 2));
    CHECK(vx_sky_format(&k, t, sizeof t, &e) == VX_OK && !strcmp(t, "map:/abs/sky.hdr:1:90"));
    /* any rotation and colour: the text gives the same bytes back */
    uint64_t x = 88172645463325252ull;
    for (int i = 0; i < 2000; i++) {
        x ^= x << 13, x ^= x >> 7, x ^= x << 17;
        double u = (double)(x >> 11) / 9007199254740992.0;
        k = (vx_sky){.type = VX_SKY_ENVMAP, .intensity = u * 7, .rotation = (u - 0.5) * 40, .path = "m.exr"};
        CHECK(vx_sky_format(&k, t, sizeof t, &e) == VX_OK && vx_sky_parse(t, &b, &e) == VX_OK);
        CHECKF(fabs(b.rotation - k.rotation) <= 1e-15 * fabs(k.rotation) && b.intensity == k.intensity,
               "'%s': rotation %.17g read back as %.17g", t, k.rotation, b.rotation);
        k = (vx_sky){.type = VX_SKY_GRADIENT, .color = {u, u / 3, u * 1e-290}, .horizon = {1 / (u + 1e-9), 0, 1e30},
                     .ground = {u * u, 0.1, -0.0}};
        CHECK(vx_sky_format(&k, t, sizeof t, &e) == VX_OK && vx_sky_parse(t, &b, &e) == VX_OK &&
              !memcmp(&k, &b, sizeof k));
    }
    /* the longest texts fit VX_SKY_SPEC_MAX */
    k = (vx_sky){.type = VX_SKY_ENVMAP, .intensity = 1.2345678901234567e-300, .rotation = -1.2345678901234567e-200};
    memset(k.path, 'p', VX_SKY_PATH_MAX);
    CHECK(vx_sky_format(&k, t, sizeof t, &e) == VX_OK && vx_sky_parse(t, &b, &e) == VX_OK && b.intensity == k.intensity);
    CHECK(vx_sky_format(&k, t, 40, &e) == VX_ERR_LIMIT && t[0] == 0);
    k.type = VX_SKY_GRADIENT, k.intensity = k.rotation = 0;
    memset(k.path, 0, sizeof k.path);
    for (int i = 0; i < 3; i++) k.color[i] = k.horizon[i] = k.ground[i] = 1.2345678901234567e-300;
    CHECK(vx_sky_format(&k, t, sizeof t, &e) == VX_OK && vx_sky_parse(t, &b, &e) == VX_OK && !memcmp(&k, &b, sizeof k));
    /* refused, saying what is wrong; the record left at the default */
    static const struct {
        const char* spec;
        const char* why;
    } badtexts[] = {{"", "R,G,B"},
                    {"1,1", "R,G,B"},
                    {"1,1,1,1", "R,G,B"},
                    {"red", "R,G,B"},
                    {"-1,0,0", "negative"},
                    {"inf,0,0", "R,G,B"},
                    {"gradient:1,1,1", "gradient:ZR"},
                    {"gradient:1,1,1:1,1,1:1,1,x", "gradient:ZR"},
                    {"map:", "map:FILE"},
                    {"map:a.exr:", "map:FILE"},
                    {"map:a.exr:1:2:3", "map:FILE"},
                    {"map:a.exr:-1", "intensity"},
                    {"default:1", "default"},
                    {"a:b:c:d:e:f", "too many"}};
    for (size_t i = 0; i < sizeof badtexts / sizeof badtexts[0]; i++) {
        memset(&k, 0x55, sizeof k);
        e = (vx_error){0};
        CHECKF(vx_sky_parse(badtexts[i].spec, &k, &e) == VX_ERR_INVALID_ARG && strstr(e.msg, badtexts[i].why) &&
                   k.type == VX_SKY_DEFAULT && k.path[0] == 0,
               "'%s': %s", badtexts[i].spec, e.msg);
    }
    char longpath[400] = "map:";
    memset(longpath + 4, 'p', 300);
    CHECK(vx_sky_parse(longpath, &k, &e) == VX_ERR_INVALID_ARG && strstr(e.msg, "255"));
    /* a path with ':' (a file from elsewhere) has no text form */
    k = (vx_sky){.type = VX_SKY_ENVMAP, .intensity = 1, .path = "c:/sky.exr"};
    CHECK(vx_sky_format(&k, t, sizeof t, &e) == VX_ERR_INVALID_ARG && strstr(e.msg, "':'") && t[0] == 0);
    k = (vx_sky){.type = VX_SKY_CONSTANT, .color = {-1, 0, 0}};
    CHECK(vx_sky_format(&k, t, sizeof t, &e) == VX_ERR_INVALID_ARG && t[0] == 0);
}

/* ---- emissive voxels as lights ---------------------------------------------------------- */

/* A scene of one 32^3 palette model with cells (x y z palette) and one
 * instance per given translation; palette 5 is emissive (_emit 2, _flux 1:
 * 4), 6 is not; colours white. world_from_grid scales by h. */
static void emissive_scene(vx_svo_scene* s, const uint32_t (*cells)[4], size_t n, double h, int instances, char* dict,
                           size_t cap) {
    vx_svo_scene_init(s, NULL);
    uint64_t* k = (uint64_t*)malloc(n * 8);
    uint8_t* p = (uint8_t*)malloc(n);
    for (size_t i = 0; i < n; i++) k[i] = vx_svo_morton(cells[i][0], cells[i][1], cells[i][2]), p[i] = (uint8_t)cells[i][3];
    vx_svo_voxels in = {.size = {32, 32, 32}, .count = n, .keys = k, .attrs = VX_ATTR_PALETTE, .palette = p};
    s->models = (vx_svo_model*)calloc(1, sizeof *s->models);
    s->model_count = 1;
    vx_error e;
    if (vx_svo_build_model(NULL, &in, &s->models[0], NULL, &e) != VX_OK) fprintf(stderr, "build: %s\n", e.msg);
    free(k), free(p);
    s->instances = (vx_svo_instance*)calloc((size_t)instances, sizeof *s->instances);
    s->instance_count = (uint32_t)instances;
    for (int i = 0; i < instances; i++) {
        vx_svo_instance* t = &s->instances[i];
        t->xform[0] = t->xform[5] = t->xform[10] = 1;
        t->xform[3] = 100.0 * i;
        t->layer = UINT32_MAX;
    }
    s->has_palette = true;
    for (int i = 0; i < 256; i++) s->palette[i] = 0xFFFFFFFFu;
    for (int a = 0; a < 3; a++) s->world_from_grid[5 * a] = h;
    s->materials = (vx_svo_material*)calloc(1, sizeof *s->materials);
    s->material_count = 1;
    s->materials[0] = mat(5, (const char* const[]){"_type", "_emit", "_emit", "2", "_flux", "1", NULL}, dict, cap);
}
static void emissive_free(vx_svo_scene* s) {
    s->materials[0].dict = NULL; /* a stack buffer */
    s->materials[0].dict_size = 0;
    vx_svo_scene_free(s);
}

/* Power of a sphere light: pi * radiance * 4 pi r^2, per channel. */
static double sphere_power(const vx_light* l, int ch) {
    return 4 * PI * PI * l->radius * l->radius * l->intensity * l->color[ch];
}

static void test_emissive_single(void) {
    char dict[128];
    vx_svo_scene s;
    const uint32_t cells[2][4] = {{3, 3, 3, 5}, {10, 10, 10, 6}};
    emissive_scene(&s, cells, 2, 0.5, 1, dict, sizeof dict);
    vx_light* L;
    uint32_t n;
    vx_error e;
    REQUIRE(vx_svo_emissive_lights(&s, NULL, &L, &n, &e) == VX_OK);
    REQUIRE(n == 1);
    CHECK(L[0].type == VX_LIGHT_SPHERE && L[0].flags == VX_LIGHT_FROM_VOXELS);
    for (int a = 0; a < 3; a++) CHECK(near(L[0].position[a], 3.5 * 0.5));
    CHECK(near(L[0].radius, sqrt(3.0) / 2 * 0.5));
    /* 6 faces of 0.25 each, radiance 4: P = pi * 4 * 6 * 0.25 */
    for (int ch = 0; ch < 3; ch++) CHECK(near(sphere_power(&L[0], ch), PI * 4 * 6 * 0.25));
    CHECK(vx_light_validate(&L[0], 0, &e) == VX_OK);
    free(L);
    /* an own emission colour: the light's power per channel is that colour's (the voxels are white) */
    vx_svo_material plain = s.materials[0];
    char dict2[128];
    s.materials[0] = mat(5, (const char* const[]){"_type", "_emit", "_emit", "2", "_flux", "1", "_emit_color", "1 0.5 0", NULL},
                         dict2, sizeof dict2);
    REQUIRE(vx_svo_emissive_lights(&s, NULL, &L, &n, &e) == VX_OK);
    REQUIRE(n == 1);
    const double own[3] = {1, 0.5, 0};
    for (int ch = 0; ch < 3; ch++)
        CHECKF(near(sphere_power(&L[0], ch), PI * 4 * own[ch] * 6 * 0.25), "channel %d: %g", ch, sphere_power(&L[0], ch));
    free(L);
    s.materials[0] = plain;
    /* no emissive material: nothing, without decoding */
    s.materials[0].id = 6 + 100;
    REQUIRE(vx_svo_emissive_lights(&s, NULL, &L, &n, &e) == VX_OK);
    CHECK(n == 0 && L == NULL);
    emissive_free(&s);
}

/* A bar of two emissive cells with a plain cell against one end: 12 - 2
 * shared - 1 covered = 9 exposed faces; the model's boundary counts as open. */
static void test_emissive_covered_faces(void) {
    char dict[128];
    vx_svo_scene s;
    const uint32_t cells[3][4] = {{4, 4, 4, 5}, {5, 4, 4, 5}, {6, 4, 4, 6}};
    emissive_scene(&s, cells, 3, 1, 1, dict, sizeof dict);
    vx_light* L;
    uint32_t n;
    vx_error e;
    REQUIRE(vx_svo_emissive_lights(&s, NULL, &L, &n, &e) == VX_OK);
    REQUIRE(n == 1);
    CHECK(near(L[0].position[0], 5) && near(L[0].position[1], 4.5) && near(L[0].position[2], 4.5));
    CHECK(near(L[0].radius, sqrt(4 + 1 + 1) / 2));
    CHECK(near(sphere_power(&L[0], 1), PI * 4 * 9));
    free(L);
    emissive_free(&s);
    const uint32_t edge[1][4] = {{0, 0, 0, 5}}; /* at the model's corner: still 6 faces */
    emissive_scene(&s, edge, 1, 1, 1, dict, sizeof dict);
    REQUIRE(vx_svo_emissive_lights(&s, NULL, &L, &n, &e) == VX_OK && n == 1);
    CHECK(near(sphere_power(&L[0], 0), PI * 4 * 6));
    free(L);
    emissive_free(&s);
}

/* A line of 20 cells along x, wider than a block, is cut at blocks of 8
 * (3 lights), of 2 (the default: 10 lights) or kept whole (block 32); the total power is the same either way and equals the brute
 * force count of faces: 20 * 4 side faces + 2 ends (+ 2 per cut, since a
 * cut face between two emissive cells is not exposed: it stays 82). Two
 * instances double the lights; a hidden one adds none. */
static void test_emissive_clusters(void) {
    char dict[128];
    vx_svo_scene s;
    uint32_t cells[20][4];
    for (uint32_t i = 0; i < 20; i++) cells[i][0] = i, cells[i][1] = 2, cells[i][2] = 2, cells[i][3] = 5;
    emissive_scene(&s, (const uint32_t(*)[4])cells, 20, 1, 3, dict, sizeof dict);
    s.instances[1].flags = VX_SVO_INSTANCE_HIDDEN;
    vx_light* L;
    uint32_t n;
    vx_error e;
    REQUIRE(vx_svo_emissive_lights(&s, &(vx_svo_emissive_desc){.block = 8}, &L, &n, &e) == VX_OK);
    REQUIRE(n == 6);
    double P = 0;
    for (uint32_t i = 0; i < 3; i++) P += sphere_power(&L[i], 0);
    CHECK(near(P, PI * 4 * 82));
    CHECK(near(L[0].position[0], 4) && near(L[1].position[0], 12) && near(L[2].position[0], 18));
    CHECK(near(L[3].position[0], 204) && near(L[5].position[0], 218)); /* instance 2 at x + 200 */
    free(L);
    REQUIRE(vx_svo_emissive_lights(&s, NULL, &L, &n, &e) == VX_OK);
    CHECK(n == 20); /* 10 per shown instance */
    P = 0;
    for (uint32_t i = 0; i < 10 && n == 20; i++) P += sphere_power(&L[i], 0);
    CHECK(near(P, PI * 4 * 82));
    free(L);
    REQUIRE(vx_svo_emissive_lights(&s, &(vx_svo_emissive_desc){.block = 32}, &L, &n, &e) == VX_OK);
    REQUIRE(n == 2);
    CHECK(near(sphere_power(&L[0], 2), PI * 4 * 82) && near(L[0].position[0], 10) && near(L[0].radius, sqrt(400 + 2) / 2));
    free(L);
    CHECK(vx_svo_emissive_lights(&s, &(vx_svo_emissive_desc){.max_lights = 3}, &L, &n, &e) == VX_ERR_LIMIT && L == NULL);
    CHECK(vx_svo_emissive_lights(&s, &(vx_svo_emissive_desc){.max_cells = 10}, &L, &n, &e) == VX_ERR_LIMIT);
    CHECK(vx_svo_emissive_lights(&s, &(vx_svo_emissive_desc){.block = 6}, &L, &n, &e) == VX_ERR_INVALID_ARG);
    emissive_free(&s);
    /* a small lamp across a block corner stays one light: only wide clusters are cut */
    const uint32_t lamp[4][4] = {{7, 7, 3, 5}, {8, 7, 3, 5}, {7, 8, 3, 5}, {8, 8, 3, 5}};
    emissive_scene(&s, lamp, 4, 1, 1, dict, sizeof dict);
    REQUIRE(vx_svo_emissive_lights(&s, NULL, &L, &n, &e) == VX_OK);
    CHECK(n == 1 && near(L[0].position[0], 8) && near(L[0].position[1], 8) && near(L[0].position[2], 3.5));
    CHECK(n == 1 && near(sphere_power(&L[0], 0), PI * 4 * 16)); /* 4 cells x (2 top/bottom + 2 outer sides) */
    free(L);
    emissive_free(&s);
}

int main(void) {
    RUN(test_material_defaults);
    RUN(test_material_ior);
    RUN(test_material_clamp_and_nan);
    RUN(test_material_emission);
    RUN(test_material_emission_color);
    RUN(test_scene_material);
    RUN(test_light_validate);
    RUN(test_sky_validate);
    RUN(test_sky_path);
    RUN(test_sky_text);
    RUN(test_emissive_single);
    RUN(test_emissive_covered_faces);
    RUN(test_emissive_clusters);
    return vx_test_finish();
}
