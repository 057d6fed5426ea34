/* tools/vox2svo/demo.c - the built-in demo scene (vox2svo --write-demo).
 *
 * A small island made by the program itself, so a fresh checkout can show
 * the whole pipeline without any input file: a terrain model, one tree model
 * placed 14 times (rotated and mirrored: instancing), a hollow tower, nested
 * groups, two layers (one hidden, left out by default) and three materials:
 * emissive lamps (the tower's top and four lamp posts around it, each head a
 * cluster of emissive voxels that vx_svo_emissive_lights turns into a
 * light), a glass greenhouse and a metal statue. Deterministic: the same
 * bytes on every run. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tools/vox2svo/demo.h"

enum { C_WATER = 1, C_SAND, C_GRASS, C_GRASS2, C_DIRT, C_ROCK, C_BARK, C_LEAF, C_LEAF2, C_STONE, C_ROOF, C_LAMP, C_RED, C_GLASS, C_METAL };

static const uint32_t demo_colors[] = {
    0, 0xFFB06A2Au, 0xFF8FD6E8u, 0xFF3FA34Du, 0xFF2E8A3Bu, 0xFF3B5A7Au, 0xFF8A8A8Au,
    0xFF2A4A6Bu, 0xFF2FB35Au, 0xFF1E8C44u, 0xFFB8B8C8u, 0xFF3040A8u, 0xFF7FF0FFu, 0xFF2020D0u, 0xFFF0E8C8u, 0xFFD8D0C8u,
};

static uint32_t rng_state = 12345u;
static uint32_t rnd(void) {
    rng_state = rng_state * 1664525u + 1013904223u;
    return rng_state >> 8;
}

static double height(int x, int y) {
    double fx = x / 128.0 - 0.5, fy = y / 128.0 - 0.5;
    double r = sqrt(fx * fx + fy * fy);
    double h = 14.0 * (0.55 - r) + 2.5 * sin(x * 0.21) * cos(y * 0.17) + 1.5 * sin((x + y) * 0.11);
    return h;
}

/* Each model is a function from a cell to its colour index (0: empty). */
typedef uint8_t (*cell_fn)(int x, int y, int z);

static uint8_t terrain_cell(int x, int y, int z) {
    int top = (int)floor(height(x, y));
    if (top < 1) return z == 0 ? C_WATER : 0; /* sea level */
    if (top > 15) top = 15;
    if (z > top) return 0;
    if (z == top) return top <= 2 ? C_SAND : ((x * 7 + y * 13) % 5 ? C_GRASS : C_GRASS2);
    return z > top - 3 ? C_DIRT : C_ROCK;
}

static uint8_t tree_cell(int x, int y, int z) {
    double dx = x - 5, dy = y - 5, dz = z - 12;
    if (z < 10 && x == 5 && y == 5) return C_BARK;
    if (z == 2 && x == 6 && y == 5) return C_BARK; /* a root: makes rotations visible */
    if (z >= 7 && dx * dx + dy * dy + dz * dz * 1.4 <= 26) return (x + z) % 3 ? C_LEAF : C_LEAF2;
    return 0;
}

static uint8_t tower_cell(int x, int y, int z) {
    double dx = x - 7.5, dy = y - 7.5, r = sqrt(dx * dx + dy * dy);
    if (z < 32) {
        bool wall = r <= 7.5 && r > 5.6;
        bool window = (z % 8 >= 3 && z % 8 <= 5) && (x == 7 || y == 7);
        return (wall && !window) || (z == 0 && r <= 7.5) ? C_STONE : 0;
    }
    if (r <= 7.5 - (z - 32) * 0.9) return z == 39 ? C_LAMP : C_ROOF;
    return 0;
}

/* A lamp post: a stone pole under a 3x3x2 head of lamp voxels (one cluster). */
static uint8_t lamp_post_cell(int x, int y, int z) {
    if (z >= 6) return C_LAMP;
    return x == 1 && y == 1 ? C_STONE : 0;
}

/* A greenhouse: glass walls and roof on a stone floor, hollow inside. */
static uint8_t greenhouse_cell(int x, int y, int z) {
    if (z == 0) return C_STONE;
    bool wall = x == 0 || x == 9 || y == 0 || y == 7 || z == 6;
    return wall ? C_GLASS : 0;
}

/* A metal ball on a stone plinth. */
static uint8_t statue_cell(int x, int y, int z) {
    if (z < 3) return x >= 2 && x <= 6 && y >= 2 && y <= 6 ? C_STONE : 0;
    double dx = x - 4, dy = y - 4, dz = z - 7;
    return dx * dx + dy * dy + dz * dz <= 16.5 ? C_METAL : 0;
}

static uint8_t crate_cell(int x, int y, int z) {
    (void)x, (void)y, (void)z;
    return C_RED;
}

static vx_result make_model(const vx_allocator* a, vx_vox_model* m, int sx, int sy, int sz, cell_fn cell) {
    m->size[0] = (uint32_t)sx;
    m->size[1] = (uint32_t)sy;
    m->size[2] = (uint32_t)sz;
    m->xyzi = (uint8_t*)vx_calloc(a, (size_t)sx * sy * sz, 4);
    if (!m->xyzi) return VX_ERR_NOMEM;
    uint32_t n = 0;
    for (int z = 0; z < sz; z++)
        for (int y = 0; y < sy; y++)
            for (int x = 0; x < sx; x++) {
                uint8_t c = cell(x, y, z);
                if (!c) continue;
                uint8_t* v = m->xyzi + 4 * (size_t)n++;
                v[0] = (uint8_t)x, v[1] = (uint8_t)y, v[2] = (uint8_t)z, v[3] = c;
            }
    m->voxel_count = n;
    return VX_OK;
}

static void set_rot(vx_vox_instance* in, int quarter_turns, bool mirror) {
    static const int c[4] = {1, 0, -1, 0}, s[4] = {0, 1, 0, -1};
    int q = quarter_turns & 3;
    int32_t r[9] = {c[q], -s[q], 0, s[q], c[q], 0, 0, 0, 1};
    if (mirror)
        for (int k = 0; k < 3; k++) r[k] = -r[k]; /* flip x: a mirror image */
    memcpy(in->rot, r, sizeof r);
}

vx_result vx_demo_scene(const vx_allocator* a, vx_vox_scene* out) {
    vx_vox_scene s;
    memset(&s, 0, sizeof s);
    s.alloc = a;
    s.version = 150;
    rng_state = 12345u;
    s.models = vx_calloc(a, 7, sizeof *s.models);
    s.instances = vx_calloc(a, 32, sizeof *s.instances);
    s.layers = vx_calloc(a, 2, sizeof *s.layers);
    s.materials = vx_calloc(a, 3, sizeof *s.materials);
    vx_result r = VX_ERR_NOMEM;
    if (!s.models || !s.instances || !s.layers || !s.materials) goto fail;
    s.model_count = 7;
    if ((r = make_model(a, &s.models[0], 128, 128, 16, terrain_cell)) || (r = make_model(a, &s.models[1], 11, 11, 18, tree_cell)) ||
        (r = make_model(a, &s.models[2], 16, 16, 40, tower_cell)) || (r = make_model(a, &s.models[3], 6, 6, 6, crate_cell)) ||
        (r = make_model(a, &s.models[4], 3, 3, 8, lamp_post_cell)) || (r = make_model(a, &s.models[5], 10, 8, 7, greenhouse_cell)) ||
        (r = make_model(a, &s.models[6], 9, 9, 12, statue_cell)))
        goto fail;

    s.has_rgba = true;
    memcpy(s.palette, vx_vox_default_palette, sizeof s.palette);
    for (unsigned i = 1; i < sizeof demo_colors / sizeof demo_colors[0]; i++) s.palette[i] = demo_colors[i];

    s.layer_count = 2;
    s.layers[0] = (vx_vox_layer){.id = 0, .hidden = false, .name = "island"};
    s.layers[1] = (vx_vox_layer){.id = 1, .hidden = true, .name = "hidden props"};

    uint32_t n = 0;
    vx_vox_instance* in = &s.instances[n++];
    *in = (vx_vox_instance){.model = 0, .layer = 0, .name = "terrain"};
    set_rot(in, 0, false);
    in->t[2] = 8;
    in = &s.instances[n++];
    *in = (vx_vox_instance){.model = 2, .layer = 0, .name = "tower"};
    set_rot(in, 1, false);
    in->t[0] = -12;
    in->t[1] = 10;
    in->t[2] = 20 + (int32_t)floor(height(52, 74));
    for (int i = 0; i < 14; i++) {
        int x, y;
        do {
            x = 8 + (int)(rnd() % 112);
            y = 8 + (int)(rnd() % 112);
        } while (height(x, y) < 3 || (abs(x - 52) < 12 && abs(y - 74) < 12));
        in = &s.instances[n++];
        *in = (vx_vox_instance){.model = 1, .layer = 0};
        snprintf(in->name, sizeof in->name, "tree %d", i);
        set_rot(in, (int)(rnd() % 4), i % 5 == 4);
        in->t[0] = x - 64;
        in->t[1] = y - 64;
        in->t[2] = (int32_t)floor(height(x, y)) + 1 + 9;
    }
    /* models standing on the ground at terrain column (x, y): a .vox
     * translation is the model's centre (size / 2, rounded down) */
    static const struct {
        uint32_t model;
        int x, y, turns;
        const char* name;
    } props[] = {{4, 40, 74, 0, "lamp post 1"}, {4, 64, 74, 0, "lamp post 2"}, {4, 52, 60, 0, "lamp post 3"},
                 {4, 52, 88, 0, "lamp post 4"}, {5, 80, 64, 1, "greenhouse"},  {6, 70, 50, 0, "statue"}};
    for (size_t i = 0; i < sizeof props / sizeof props[0]; i++) {
        in = &s.instances[n++];
        *in = (vx_vox_instance){.model = props[i].model, .layer = 0};
        snprintf(in->name, sizeof in->name, "%s", props[i].name);
        set_rot(in, props[i].turns, false);
        in->t[0] = props[i].x - 64;
        in->t[1] = props[i].y - 64;
        in->t[2] = (int32_t)floor(height(props[i].x, props[i].y)) + 1 + (int32_t)s.models[props[i].model].size[2] / 2;
    }
    in = &s.instances[n++];
    *in = (vx_vox_instance){.model = 3, .layer = 1, .name = "crate (hidden layer)"};
    set_rot(in, 0, false);
    in->t[2] = 40;
    s.instance_count = n;

    /* MagicaVoxel MATL dictionaries (_ior is the index of refraction - 1) */
    static const char lamp[] = "_type\0_emit\0_emit\0" "0.8\0_flux\0" "2";
    static const char glass[] = "_type\0_glass\0_trans\0" "0.9\0_rough\0" "0.05\0_ior\0" "0.5";
    static const char metal[] = "_type\0_metal\0_metal\0" "1\0_rough\0" "0.2\0_spec\0" "0.5";
    static const struct {
        uint32_t id;
        const char* dict;
        uint32_t size; /* includes the last NUL */
    } mats[] = {{C_LAMP, lamp, sizeof lamp}, {C_GLASS, glass, sizeof glass}, {C_METAL, metal, sizeof metal}};
    for (uint32_t i = 0; i < 3; i++) {
        s.materials[i].id = mats[i].id;
        s.materials[i].dict_size = mats[i].size;
        s.materials[i].dict = vx_alloc(a, mats[i].size);
        if (!s.materials[i].dict) goto fail;
        memcpy(s.materials[i].dict, mats[i].dict, mats[i].size);
        s.material_count = i + 1;
    }
    s.has_scene_graph = true;
    *out = s;
    return VX_OK;
fail:
    vx_vox_scene_free(&s);
    return r ? r : VX_ERR_NOMEM;
}

/* The island as an animation of `frames` frames: the tower slides east one
 * cell per frame, the first four trees turn a quarter every 6 frames (a new
 * keyframe each time), the terrain and the other trees stand still, so most
 * voxels are shared by every frame. */
vx_result vx_demo_animation(const vx_allocator* a, uint32_t frames, vx_vox_scene* out) {
    vx_result r = vx_demo_scene(a, out);
    if (r != VX_OK || frames < 2) return r;
    vx_vox_scene* s = out;
    uint32_t I = s->instance_count;
    s->frame_instances = vx_calloc(a, (size_t)frames * I, sizeof *s->frame_instances);
    if (!s->frame_instances) {
        vx_vox_scene_free(s);
        return VX_ERR_NOMEM;
    }
    s->frame_count = frames;
    for (uint32_t f = 0; f < frames; f++) {
        vx_vox_instance* fi = s->frame_instances + (size_t)f * I;
        memcpy(fi, s->instances, (size_t)I * sizeof *fi);
        fi[1].t[0] += (int32_t)f; /* the tower */
        for (uint32_t k = 2; k < 6 && k < I; k++) {
            int32_t q = (int32_t)(f / 6 % 4), R[9] = {0}, t[9];
            R[8] = 1;
            R[0] = q == 0 || q == 2 ? (q ? -1 : 1) : 0, R[4] = R[0];
            R[1] = q == 1 ? -1 : q == 3 ? 1 : 0, R[3] = -R[1];
            for (int i = 0; i < 3; i++) /* the turn after the tree's own rotation */
                for (int j = 0; j < 3; j++)
                    t[3 * i + j] = R[3 * i] * fi[k].rot[j] + R[3 * i + 1] * fi[k].rot[3 + j] + R[3 * i + 2] * fi[k].rot[6 + j];
            memcpy(fi[k].rot, t, sizeof t);
        }
    }
    return VX_OK;
}

