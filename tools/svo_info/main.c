/* tools/svo_info/main.c - inspect, verify, dump and export .svo files. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "convert/convert.h"
#include "convert/export.h"
#include "tools/common/light.h"
#include "tools/common/tool.h"

typedef struct options {
    const char* in;
    bool verify;
    bool dump;
    bool all;
    bool models;
    bool frame_set;
    uint32_t frame;
    const char* to_vox;
    bool quantize;
    const char* to_glb;
    const char* to_vdb;
    bool vdb_models;
    bool quiet;
    uint64_t max_memory; /* 0: no limit */
} options;

_Noreturn static void usage(int status) {
    FILE* f = status == 0 ? stdout : stderr;
    fprintf(f,
            "Usage: %s FILE.svo [options]\n"
            "Which: prints the header, sections and per-model statistics of a .svo file;\n"
            "       verifies, dumps or exports it.\n"
            "Options:\n"
            "    --verify         check every checksum and the whole structure; the exit\n"
            "                     status says the result (0 valid, 1 invalid)\n"
            "    --dump           print every voxel of the scene in grid cells, one per line\n"
            "                     as 'x y z r g b a' (instances applied, colours from the palette)\n"
            "    --all            with --dump, --to-glb and --to-vdb: include hidden instances and layers\n"
            "    --models         list every model, instance, light, material and frame (default: the first 16)\n"
            "    --frame N        an animation's frame N for --dump, --to-glb, --to-vdb, --to-vox and the\n"
            "                     instance list (default: frame 0; --to-vox: every frame)\n"
            "    --to-vox OUT     write the scene back to a MagicaVoxel .vox file; a model over 256 cells\n"
            "                     a side is split into 256^3 pieces (those holding cells), each\n"
            "                     instance of it a group of the pieces placing every cell where it was;\n"
            "                     more than 255 colours are refused (--quantize)\n"
            "    --quantize       with --to-vox: more than 255 colours are mapped to a 255-entry\n"
            "                     palette (median cut, each colour to its nearest entry), with a\n"
            "                     warning giving the colour count and the largest and mean error\n"
            "                     (default: refused; 255 colours or fewer are always kept exact)\n"
            "    --to-glb OUT     write the scene as binary glTF: one mesh per model (greedy-meshed\n"
            "                     voxel surface, vertex colours), one node per instance; turned from\n"
            "                     voxkit's +Z up to glTF's +Y up; MATL metal, glass and emission become\n"
            "                     glTF materials (an emission without _emit_color: the mean colour of\n"
            "                     its cells x strength); the lights become KHR_lights_punctual lights\n"
            "                     (sphere: a point, rect: a spot; voxkit's exact record in their extras,\n"
            "                     which vox2svo reads back); a sky goes into the scene's extras\n"
            "                     (voxkit_sky, read back by vox2svo; other glTF tools ignore it)\n"
            "    --to-vdb OUT     write the scene as OpenVDB grids: by default the flattened scene (the\n"
            "                     --dump cells) as a fog volume 'density' and a vec3 grid 'color' (linear\n"
            "                     RGB), index space = grid cells, transform = world_from_grid (+Z up,\n"
            "                     as Blender's)\n"
            "    --vdb-models     with --to-vdb: instead a grid pair 'NAME/density', 'NAME/color' per\n"
            "                     instance in model cells with its transform; instances of one model\n"
            "                     share one tree\n"
            "    --max-memory SIZE  refuse a file that needs more memory than SIZE to read (e.g.\n"
            "                     512M, 4G; the file's bytes count; default: no limit)\n"
            "    -q, --quiet      print only errors (and the dump)\n"
            "    -h, --help       print this help and exit\n"
            "    --version        print the tool and format versions and exit\n"
            "Examples:\n"
            "    %s castle.svo\n"
            "    %s castle.svo --verify\n"
            "    %s castle.svo --dump | sort > cells.txt\n"
            "    %s walk.svo --dump --frame 3 | sort > frame3.txt\n"
            "    %s castle.svo --to-vox castle2.vox\n"
            "    %s scan.svo --to-vox scan.vox --quantize\n"
            "    %s castle.svo --to-glb castle.glb\n"
            "    %s castle.svo --to-vdb castle.vdb\n",
            vx_tool_name, vx_tool_name, vx_tool_name, vx_tool_name, vx_tool_name, vx_tool_name, vx_tool_name, vx_tool_name,
            vx_tool_name);
    exit(status);
}

#define usage_error(...) vx_tool_usage_error(usage, __VA_ARGS__)

static options parse(int argc, char** argv) {
    options o = {0};
    if (argc == 1) usage(2);
    for (int i = 1; i < argc; i++) {
        const char* a = argv[i];
        if (!strcmp(a, "-h") || !strcmp(a, "-help") || !strcmp(a, "--help")) usage(0);
        else if (!strcmp(a, "--version") || !strcmp(a, "-version")) {
            printf("%s %s (.svo format version %u)\n", vx_tool_name, VX_VERSION_STRING, VX_SVO_FORMAT_VERSION);
            exit(0);
        } else if (!strcmp(a, "--verify")) o.verify = true;
        else if (!strcmp(a, "--dump")) o.dump = true;
        else if (!strcmp(a, "--max-memory")) {
            if (!vx_tool_parse_bytes(vx_tool_arg(argc, argv, &i, usage), &o.max_memory) || !o.max_memory)
                usage_error("bad --max-memory value '%s' (bytes, e.g. 512M or 4G)", argv[i]);
        }
        else if (!strcmp(a, "--all")) o.all = true;
        else if (!strcmp(a, "--models")) o.models = true;
        else if (!strcmp(a, "--frame")) {
            if (i + 1 >= argc || !vx_tool_parse_u32(argv[i + 1], &o.frame)) usage_error("option %s needs a frame number", a);
            o.frame_set = true;
            i++;
        }
        else if (!strcmp(a, "--to-vox")) o.to_vox = vx_tool_arg(argc, argv, &i, usage);
        else if (!strcmp(a, "--quantize")) o.quantize = true;
        else if (!strcmp(a, "--to-glb")) o.to_glb = vx_tool_arg(argc, argv, &i, usage);
        else if (!strcmp(a, "--to-vdb")) o.to_vdb = vx_tool_arg(argc, argv, &i, usage);
        else if (!strcmp(a, "--vdb-models")) o.vdb_models = true;
        else if (!strcmp(a, "-q") || !strcmp(a, "--quiet")) o.quiet = true;
        else if (a[0] == '-' && a[1]) usage_error("\"%s\" is not a valid option", a);
        else if (!o.in) o.in = a;
        else usage_error("unexpected argument '%s'", a);
    }
    if (!o.in) usage_error("%s", "expected a .svo file");
    if (o.quantize && !o.to_vox) usage_error("%s", "--quantize needs --to-vox");
    return o;
}

/* Descriptors reachable from the root, each shared block counted once. */
static uint64_t count_descriptors(const vx_svo_model* m) {
    if (m->root >= m->node_count) return 0;
    uint8_t* seen = calloc((m->node_count + 7) / 8, 1);
    uint32_t* stack = malloc(sizeof(uint32_t) * ((size_t)m->depth * 8 + 8));
    if (!seen || !stack) {
        free(seen);
        free(stack);
        return 0;
    }
    uint64_t n = 0;
    size_t sp = 0;
    stack[sp++] = m->root;
    while (sp) {
        uint32_t i = stack[--sp];
        if (seen[i / 8] & (1u << (i % 8))) continue;
        seen[i / 8] |= (uint8_t)(1u << (i % 8));
        n++;
        uint32_t d = m->nodes[i];
        uint32_t inner = vx_svo_desc_valid(d) & ~vx_svo_desc_leaf(d);
        if (!inner) continue;
        uint32_t p = vx_svo_desc_ptr(d);
        uint32_t block = vx_svo_desc_far(d) ? m->nodes[i - p] : i - p;
        for (uint32_t k = 0, c = (uint32_t)__builtin_popcount(inner); k < c; k++) stack[sp++] = block + k;
    }
    free(seen);
    free(stack);
    return n;
}

static void attrs_str(uint32_t a, char* buf, size_t n) {
    buf[0] = 0;
    static const char* names[] = {"palette", "rgba8", "normal", "material", "density"};
    for (int i = 0; i < 5; i++)
        if (a & (1u << i)) {
            if (buf[0]) strncat(buf, "+", n - strlen(buf) - 1);
            strncat(buf, names[i], n - strlen(buf) - 1);
        }
    if (!buf[0]) snprintf(buf, n, "geometry only");
}

static bool xform_is_identity(const double* m) {
    static const double id[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
    return !memcmp(m, id, sizeof id);
}

/* One line per frame: what it shows and how it differs from the frame before. */
static void print_frames(const options* o, const vx_svo_scene* s) {
    uint32_t F = vx_svo_scene_frames(s);
    if (F < 2) return;
    if (s->frame_rate > 0) printf("frames       %u at %g frames per second (%g s)\n", F, s->frame_rate, F / s->frame_rate);
    else printf("frames       %u (frame rate not known)\n", F);
    uint32_t shown = o->models || F <= 16 ? F : 16;
    for (uint32_t f = 0; f < shown; f++) {
        vx_svo_scene v;
        vx_svo_scene_frame(s, f, &v);
        const vx_svo_instance* prev = f ? vx_svo_scene_frame_instances(s, f - 1) : NULL;
        uint32_t shown_inst = 0, changed = 0;
        uint64_t voxels = 0;
        for (uint32_t i = 0; i < v.instance_count; i++) {
            if (vx_svo_instance_visible(&v, i)) shown_inst++, voxels += v.models[v.instances[i].model].voxel_count;
            if (prev && (prev[i].model != v.instances[i].model || prev[i].flags != v.instances[i].flags ||
                         memcmp(prev[i].xform, v.instances[i].xform, sizeof prev[i].xform)))
                changed++;
        }
        printf("frame %-6u %u instances shown, %s voxels", f, shown_inst, vx_tool_num(voxels));
        if (f) printf(", %u instances changed", changed);
        printf("\n");
    }
    if (shown < F) printf("  ... %u more frames (--models lists all)\n", F - shown);
}

static void print_info(const options* o, const vx_svo_file_info* fi, const vx_svo_scene* s, const vx_svo_chunk_stats* cs) {
    printf("file         %s (%s bytes, .svo format version %u)\n", o->in, vx_tool_num(fi->file_size), fi->version);
    printf("sections     %u\n", fi->section_count);
    for (uint32_t i = 0; i < fi->section_count && i < 64; i++) {
        const vx_svo_section_info* si = &fi->sections[i];
        printf("  %-4s  offset %10llu  size %10llu  crc %08x %s%s\n", si->tag, (unsigned long long)si->offset,
               (unsigned long long)si->size, si->crc, si->crc_ok ? "ok" : "BAD",
               si->known ? "" : "  (unknown, skipped)");
    }
    uint64_t voxels = 0;
    for (uint32_t i = 0; i < s->model_count; i++) voxels += s->models[i].voxel_count;
    printf("scene        %u models, %u instances, %u layers, %u materials, palette %s\n", s->model_count,
           s->instance_count, s->layer_count, s->material_count, s->has_palette ? "yes" : "no");
    printf("bounds       [%g %g %g] - [%g %g %g] (grid cells)\n", s->bounds_min[0], s->bounds_min[1], s->bounds_min[2],
           s->bounds_max[0], s->bounds_max[1], s->bounds_max[2]);
    if (xform_is_identity(s->world_from_grid)) printf("world        grid cells are world units\n");
    else {
        const double* w = s->world_from_grid;
        printf("world        x' = [%g %g %g | %g]  y' = [%g %g %g | %g]  z' = [%g %g %g | %g]\n", w[0], w[1], w[2], w[3],
               w[4], w[5], w[6], w[7], w[8], w[9], w[10], w[11]);
    }
    printf("voxels       %s in models, %.3f bytes/voxel for the whole file\n", vx_tool_num(voxels),
           voxels ? (double)fi->file_size / (double)voxels : 0.0);
    if (cs->models) { /* which codec the chunked form uses (docs/FORMAT.md 3.6) */
        printf("chunked      %u models, %s chunks: %s zstd, %s", cs->models, vx_tool_num(cs->deflate + cs->zstd + cs->zstd_plain),
               vx_tool_num(cs->zstd), vx_tool_num(cs->zstd_plain));
        printf(" zstd without differences, %s DEFLATE; %s bytes of words and records in %s (%.3f)\n", vx_tool_num(cs->deflate),
               vx_tool_num(cs->raw_bytes), vx_tool_num(cs->coded_bytes),
               cs->raw_bytes ? (double)cs->coded_bytes / (double)cs->raw_bytes : 0.0);
    }
    uint32_t shown = o->models ? s->model_count : (s->model_count < 16 ? s->model_count : 16);
    for (uint32_t i = 0; i < shown; i++) {
        const vx_svo_model* m = &s->models[i];
        char at[64];
        attrs_str(m->attrs, at, sizeof at);
        uint64_t nd = count_descriptors(m);
        const char* root = m->root == VX_SVO_ROOT_EMPTY ? " (empty)" : m->root == VX_SVO_ROOT_LEAF ? " (one leaf)" : "";
        printf("model %-6u %ux%ux%u, depth %u, %s voxels%s, %s descriptors, %s node words, %s attribute records (%s)\n",
               i, m->size[0], m->size[1], m->size[2], m->depth, vx_tool_num(m->voxel_count), root, vx_tool_num(nd),
               vx_tool_num(m->node_count), vx_tool_num(m->attr_count), at);
    }
    if (shown < s->model_count) printf("  ... %u more models (--models lists all)\n", s->model_count - shown);
    print_frames(o, s);
    shown = o->models ? s->instance_count : (s->instance_count < 16 ? s->instance_count : 16);
    const vx_svo_instance* inst = vx_svo_scene_frame_instances(s, o->frame); /* checked by main */
    if (vx_svo_scene_frames(s) > 1) printf("instances of frame %u:\n", o->frame);
    for (uint32_t i = 0; i < shown; i++) {
        const vx_svo_instance* in = &inst[i];
        const double* x = in->xform;
        printf("instance %-3u model %u, layer %s%s%s, t = (%g %g %g), M = [%g %g %g; %g %g %g; %g %g %g]%s%s%s\n", i,
               in->model, in->layer < s->layer_count ? "" : "-",
               in->layer < s->layer_count ? s->layers[in->layer].name : "",
               in->flags & VX_SVO_INSTANCE_HIDDEN ? " (hidden)" : "", x[3], x[7], x[11], x[0], x[1], x[2], x[4], x[5],
               x[6], x[8], x[9], x[10], in->name[0] ? ", \"" : "", in->name, in->name[0] ? "\"" : "");
    }
    if (shown < s->instance_count) printf("  ... %u more instances (--models lists all)\n", s->instance_count - shown);
    char line[512];
    vx_tool_sky_str(&s->sky, line, sizeof line);
    printf("sky          %s\n", line);
    printf("lights       %u stored", s->light_count);
    uint64_t emissive = 0;
    for (uint32_t i = 0; i < s->material_count; i++) emissive += vx_svo_material_resolve(&s->materials[i]).emission > 0;
    if (emissive) {
        /* what a renderer derives from the emissive voxels (not stored) */
        vx_light* vl = NULL;
        uint32_t nv = 0;
        vx_error e = {0};
        if (vx_svo_emissive_lights(s, NULL, &vl, &nv, &e) == VX_OK)
            printf(", %u from the voxels of %llu emissive materials (derived when rendering)", nv, (unsigned long long)emissive);
        else
            printf(", %llu emissive materials (%s)", (unsigned long long)emissive, e.msg);
        vx_free(NULL, vl);
    }
    printf("\n");
    shown = o->models ? s->light_count : (s->light_count < 16 ? s->light_count : 16);
    for (uint32_t i = 0; i < shown; i++) {
        vx_tool_light_str(&s->lights[i], line, sizeof line);
        printf("light %-6u %s\n", i, line);
    }
    if (shown < s->light_count) printf("  ... %u more lights (--models lists all)\n", s->light_count - shown);
    /* the materials as the renderers read them (vx_svo_material_resolve: defaults and clamps applied) */
    shown = o->models ? s->material_count : (s->material_count < 16 ? s->material_count : 16);
    for (uint32_t i = 0; i < shown; i++) {
        vx_material m = vx_svo_material_resolve(&s->materials[i]);
        static const char* const types[] = {"diffuse", "metal", "glass", "emit"};
        printf("material %-4u %s", s->materials[i].id, (unsigned)m.type < 4 ? types[m.type] : "?");
        if (m.type == VX_MATERIAL_METAL)
            printf(", roughness %g, metalness %g, specular %g", m.roughness, m.metalness, m.specular);
        else if (m.type == VX_MATERIAL_GLASS)
            printf(", roughness %g, ior %g, transmission %g", m.roughness, m.ior, m.transmission);
        if (m.emission > 0) {
            printf(", emission %g", m.emission);
            const double* c = m.emission_color;
            if (c[0] > 0 || c[1] > 0 || c[2] > 0) printf(" of colour %g %g %g", c[0], c[1], c[2]);
            else printf(" of the voxels' colour");
        }
        printf("\n");
    }
    if (shown < s->material_count) printf("  ... %u more materials (--models lists all)\n", s->material_count - shown);
}

/* --to-glb's lights: how many, and which other glTF readers see only
 * approximately (voxkit reads its extras back exactly). */
static void print_glb_lights(const options* o, const vx_svo_scene* s, const vx_conv_glb_stats* gs) {
    printf("lights       %u written (KHR_lights_punctual), %u approximated for other glTF readers%s\n", gs->lights,
           gs->lights_approximated, gs->lights_approximated ? " (exact in extras.voxkit_light)" : "");
    uint32_t shown = 0, limit = o->models ? UINT32_MAX : 16;
    for (uint32_t i = 0; i < s->light_count; i++) {
        const char* why = (s->lights[i].flags & VX_LIGHT_FROM_VOXELS) ? NULL : vx_conv_glb_light_approx(&s->lights[i]);
        if (!why || shown++ >= limit) continue;
        printf("  light %-4u %s\n", i, why);
    }
    if (shown > limit) printf("  ... %u more approximated lights (--models lists all)\n", shown - limit);
}

typedef struct dump_ctx {
    const vx_svo_scene* s;
    const vx_svo_model* m;
    const double* x;
    char buf[1 << 16];
    size_t len;
} dump_ctx;

static void dump_flush(dump_ctx* c) {
    fwrite(c->buf, 1, c->len, stdout);
    c->len = 0;
}

static bool dump_voxel(void* user, uint32_t x, uint32_t y, uint32_t z, uint32_t attr) {
    dump_ctx* c = (dump_ctx*)user;
    const double* M = c->x;
    double p[3] = {x + 0.5, y + 0.5, z + 0.5};
    long long g[3];
    for (int r = 0; r < 3; r++) g[r] = (long long)floor(M[r * 4] * p[0] + M[r * 4 + 1] * p[1] + M[r * 4 + 2] * p[2] + M[r * 4 + 3]);
    uint32_t col = vx_svo_attr_color(c->s, c->m, attr);
    if (c->len > sizeof c->buf - 128) dump_flush(c);
    c->len += (size_t)snprintf(c->buf + c->len, sizeof c->buf - c->len, "%lld %lld %lld %u %u %u %u\n", g[0], g[1],
                               g[2], col & 0xFF, (col >> 8) & 0xFF, (col >> 16) & 0xFF, col >> 24);
    return true;
}

static int dump(const options* o, const vx_svo_scene* s) {
    dump_ctx* c = malloc(sizeof *c);
    if (!c) return vx_tool_errorf("out of memory");
    c->s = s;
    c->len = 0;
    for (uint32_t i = 0; i < s->instance_count; i++) {
        const vx_svo_instance* in = &s->instances[i];
        bool hidden = !vx_svo_instance_visible(s, i);
        if (hidden && !o->all) continue;
        c->m = &s->models[in->model];
        c->x = in->xform;
        vx_error err = {0};
        if (vx_svo_decode_model(c->m, dump_voxel, c, &err) != VX_OK) {
            dump_flush(c);
            free(c);
            return vx_tool_error(o->in, &err);
        }
    }
    dump_flush(c);
    free(c);
    return fflush(stdout) == 0 ? 0 : vx_tool_errorf("cannot write the dump");
}

int main(int argc, char** argv) {
    vx_tool_init(argc, argv);
    options o = parse(argc, argv);
    vx_error err = {0};
    uint8_t* data = NULL;
    size_t size = 0;
    vx_budget budget; /* --max-memory: the file's bytes and the scene; outlives the scene */
    vx_budget_init(&budget, o.max_memory, NULL);
    const vx_allocator* A = o.max_memory ? &budget.allocator : NULL;
    if (vx_file_read(o.in, A, (uint64_t)1 << 40, &data, &size, &err) != VX_OK)
        return vx_tool_error_budget(o.in, &err, &budget);
    vx_svo_file_info fi;
    if (vx_svo_probe(data, size, &fi, &err) != VX_OK) {
        vx_free(A, data);
        return vx_tool_error(o.in, &err);
    }
    vx_svo_scene s;
    vx_svo_chunk_stats cs;
    vx_result r = vx_svo_read(&(vx_svo_read_desc){.alloc = A, .chunk_stats = &cs}, data, size, &s, &err);
    vx_free(A, data);
    if (r != VX_OK) {
        if (o.verify && !o.quiet) printf("%s: INVALID\n", o.in);
        return vx_tool_error_budget(o.in, &err, &budget);
    }
    int status = 0;
    vx_svo_scene view; /* the frame that --dump, --to-glb and --frame's --to-vox show */
    if (!vx_svo_scene_frame(&s, o.frame, &view)) {
        uint32_t frames = vx_svo_scene_frames(&s);
        vx_svo_scene_free(&s);
        return vx_tool_errorf("%s: no frame %u (the scene has %u)", o.in, o.frame, frames);
    }
    if (!o.quiet && !o.dump) print_info(&o, &fi, &s, &cs);
    if (o.verify && !o.quiet) printf("%s: valid (%u sections, checksums and structure verified)\n", o.in, fi.section_count);
    if (o.dump) status = dump(&o, &view);
    if (status == 0 && o.to_vox) {
        vx_vox_scene v;
        vx_conv_vox_export_stats xs = {0};
        r = vx_conv_svo_to_vox_ex(&(vx_conv_vox_export_desc){.quantize = o.quantize}, o.frame_set ? &view : &s, &v, &xs, &err);
        if (r == VX_OK) {
            r = vx_vox_write_file(NULL, &v, o.to_vox, &err);
            vx_vox_scene_free(&v);
        }
        if (r == VX_OK && xs.quantized)
            fprintf(stderr,
                    "%s: warning: %s: %u distinct colours quantized to a 255-entry palette: colour error (RGBA distance, "
                    "0-255 a channel) max %.2f, mean %.2f\n",
                    vx_tool_name, o.to_vox, xs.colors, xs.max_error, xs.mean_error);
        if (r == VX_ERR_UNSUPPORTED && xs.colors > 255) /* the library names its desc field */
            snprintf(err.msg + strlen(err.msg), sizeof err.msg - strlen(err.msg), " (--quantize)");
        if (r != VX_OK) status = vx_tool_error(o.to_vox, &err);
        else if (!o.quiet && !o.dump) printf("wrote        %s\n", o.to_vox);
    }
    vx_conv_export_desc xd = {.all = o.all, .vdb_models = o.vdb_models, .svo_path = o.in};
    if (status == 0 && o.to_glb) {
        vx_conv_glb_stats gs;
        r = vx_conv_svo_to_glb_file(&xd, &view, o.to_glb, &gs, &err);
        if (r == VX_ERR_UNSUPPORTED) status = vx_tool_errorf("%s", err.msg);
        else if (r != VX_OK) status = vx_tool_error(o.to_glb, &err);
        else if (!o.quiet && !o.dump) {
            printf("wrote        %s (%u meshes, %u nodes, %s quads for %s exposed voxel faces, meshed in %.3f s)\n",
                   o.to_glb, gs.meshes, gs.nodes, vx_tool_num(gs.quads), vx_tool_num(gs.faces), gs.seconds_mesh);
            if (gs.lights) print_glb_lights(&o, &view, &gs);
        }
    }
    if (status == 0 && o.to_vdb) {
        vx_conv_vdb_stats vs;
        r = vx_conv_svo_to_vdb_file(&xd, &view, o.to_vdb, &vs, &err);
        if (r == VX_ERR_UNSUPPORTED) status = vx_tool_errorf("%s", err.msg);
        else if (r != VX_OK) status = vx_tool_error(o.to_vdb, &err);
        else if (!o.quiet && !o.dump)
            printf("wrote        %s (%u grids, %s active voxels%s)\n", o.to_vdb, vs.grids, vx_tool_num(vs.voxels),
                   vs.colors ? ", colours" : "");
    }
    vx_svo_scene_free(&s);
    return status;
}
