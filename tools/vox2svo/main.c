/* tools/vox2svo/main.c - convert a MagicaVoxel scene, a glTF mesh or an
 * OpenVDB grid into a .svo file and print what the minimization did. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "convert/convert.h"
#include "tools/common/tool.h"
#include "tools/vox2svo/demo.h"
#ifdef VX_HAVE_MESH
#include "convert/mesh.h"
#endif
#ifdef VX_HAVE_VDB
#include "convert/volume.h"
#endif

typedef struct options {
    const char* in;
    const char* out;
    const char* write_demo;
    uint32_t frame;
    bool keep_hidden;
    bool no_collapse, no_dag;
    bool quiet, verbose;
    /* meshes */
    uint32_t res;
    bool scene_set;
    uint32_t scene;
    bool solid, normals;
    /* OpenVDB */
    const char* grid;
    bool threshold_set;
    double threshold;
    bool density;
    const char* color;
} options;

static options default_options(void) {
    options o = {0};
    o.res = 256;
    return o;
}

_Noreturn static void usage(int status) {
    options d = default_options();
    FILE* f = status == 0 ? stdout : stderr;
    fprintf(f,
            "Usage: %s IN.{vox,gltf,glb,vdb} OUT.svo [options]\n"
            "       %s --write-demo OUT.vox\n"
            "Which: converts a voxel scene, a triangle mesh or a volume into a compact sparse voxel\n"
            "       octree file (.svo): one Laine-Karras octree per model after tree minimization,\n"
            "       instances with their transforms. The reader is picked by the file extension.\n"
            "Options:\n"
            "    --frame N        animation frame of a .vox scene (default: %u)\n"
            "    --keep-hidden    keep hidden nodes, groups and layers of a .vox scene\n"
            "    --no-collapse    skip minimization step 1 (uniform full subtrees -> one leaf)\n"
            "    --no-dag         skip minimization step 2 (share identical subtrees)\n"
            "    --res N          meshes: voxels along the longest side (default: %u)\n"
            "    --scene N        meshes: glTF scene to convert (default: the file's default scene)\n"
            "    --solid          meshes and level sets: fill the inside, not only the surface\n"
            "    --normals        meshes: store oct-encoded normals\n"
            "    --grid NAME      OpenVDB: grid to convert (default: the first scalar grid)\n"
            "    --threshold X    OpenVDB fog volumes: keep active voxels with value >= X\n"
            "                     (default: any active value > 0)\n"
            "    --density        OpenVDB fog volumes: keep the values as a density attribute\n"
            "    --color NAME     OpenVDB: vec3 grid giving colours\n"
            "    --write-demo F   write the built-in demo scene (a .vox file) to F and exit\n"
            "    -q, --quiet      print nothing but errors\n"
            "    -v, --verbose    print warnings and details\n"
            "    -h, --help       print this help and exit\n"
            "    --version        print the tool and format versions and exit\n"
            "Examples:\n"
            "    %s castle.vox castle.svo\n"
            "    %s --write-demo demo.vox && %s demo.vox demo.svo\n"
            "    %s DamagedHelmet.glb helmet.svo --res 1024\n"
            "    %s smoke.vdb smoke.svo --density\n",
            vx_tool_name, vx_tool_name, d.frame, d.res, vx_tool_name, vx_tool_name, vx_tool_name, vx_tool_name,
            vx_tool_name);
    exit(status);
}

#define usage_error(...) vx_tool_usage_error(usage, __VA_ARGS__)

static const char* need_arg(int argc, char** argv, int* i) {
    if (*i + 1 >= argc) usage_error("option %s needs an argument", argv[*i]);
    return argv[++*i];
}

static options parse(int argc, char** argv) {
    options o = default_options();
    int npos = 0;
    for (int i = 1; i < argc; i++) {
        const char* a = argv[i];
        if (!strcmp(a, "-h") || !strcmp(a, "-help") || !strcmp(a, "--help")) usage(0);
        else if (!strcmp(a, "--version") || !strcmp(a, "-version")) {
            printf("%s %s (.svo format version %u; reads .vox versions 150 and 200)\n", vx_tool_name, VX_VERSION_STRING,
                   VX_SVO_FORMAT_VERSION);
            exit(0);
        } else if (!strcmp(a, "--frame")) {
            if (!vx_tool_parse_u32(need_arg(argc, argv, &i), &o.frame)) usage_error("bad --frame value '%s'", argv[i]);
        } else if (!strcmp(a, "--keep-hidden")) o.keep_hidden = true;
        else if (!strcmp(a, "--no-collapse")) o.no_collapse = true;
        else if (!strcmp(a, "--no-dag")) o.no_dag = true;
        else if (!strcmp(a, "--res")) {
            if (!vx_tool_parse_u32(need_arg(argc, argv, &i), &o.res) || o.res < 1 || o.res > 65536)
                usage_error("bad --res value '%s' (1 to 65536)", argv[i]);
        } else if (!strcmp(a, "--scene")) {
            if (!vx_tool_parse_u32(need_arg(argc, argv, &i), &o.scene)) usage_error("bad --scene value '%s'", argv[i]);
            o.scene_set = true;
        } else if (!strcmp(a, "--solid")) o.solid = true;
        else if (!strcmp(a, "--normals")) o.normals = true;
        else if (!strcmp(a, "--grid")) o.grid = need_arg(argc, argv, &i);
        else if (!strcmp(a, "--threshold")) {
            if (!vx_tool_parse_double(need_arg(argc, argv, &i), &o.threshold))
                usage_error("bad --threshold value '%s'", argv[i]);
            o.threshold_set = true;
        } else if (!strcmp(a, "--density")) o.density = true;
        else if (!strcmp(a, "--color")) o.color = need_arg(argc, argv, &i);
        else if (!strcmp(a, "--write-demo")) o.write_demo = need_arg(argc, argv, &i);
        else if (!strcmp(a, "-q") || !strcmp(a, "--quiet")) o.quiet = true;
        else if (!strcmp(a, "-v") || !strcmp(a, "--verbose")) o.verbose = true;
        else if (a[0] == '-' && a[1]) usage_error("\"%s\" is not a valid option", a);
        else if (npos == 0) { o.in = a; npos++; }
        else if (npos == 1) { o.out = a; npos++; }
        else usage_error("unexpected argument '%s'", a);
    }
    if (o.write_demo) {
        if (npos) usage_error("%s", "--write-demo takes no other file arguments");
        return o;
    }
    if (argc == 1) usage(2);
    if (npos != 2) usage_error("%s", "expected an input file and an output .svo file");
    return o;
}

static void print_stats(const options* o, const char* kind, const vx_conv_stats* cs, uint64_t in_bytes,
                        uint64_t out_bytes, double t_read, double t_convert, double t_write) {
    if (o->quiet) return;
    const vx_svo_build_stats* b = &cs->build;
    double vox = b->voxels ? (double)b->voxels : 1.0;
    printf("%s: %s -> %s\n", vx_tool_name, o->in, o->out);
    printf("  input        %s, %s bytes\n", kind, vx_tool_num(in_bytes));
    printf("  voxels       %s (%s given)\n", vx_tool_num(b->voxels), vx_tool_num(b->input_voxels));
    printf("  models       %u, instances %u\n", cs->models, cs->instances);
    printf("  descriptors  plain %s -> collapsed %s -> dag %s", vx_tool_num(b->desc_plain),
           vx_tool_num(b->desc_collapsed), vx_tool_num(b->desc_dag));
    if (b->desc_plain)
        printf("  (%.1f%% of plain)", 100.0 * (double)b->desc_dag / (double)b->desc_plain);
    printf("\n");
    printf("  far pointers %s, attribute records %s\n", vx_tool_num(b->far_pointers), vx_tool_num(b->attr_records));
    /* what the tracer holds: node words and records, before the file's entropy coding */
    printf("  in memory    %s bytes, %.3f bytes/voxel\n", vx_tool_num(b->bytes), (double)b->bytes / vox);
    printf("  output       %s bytes, %.3f bytes/voxel", vx_tool_num(out_bytes), (double)out_bytes / vox);
    if (in_bytes && !strcmp(kind, ".vox")) printf(" (input %.3f)", (double)in_bytes / vox);
    printf("\n");
    printf("  time         %.1f ms (read %.1f, convert %.1f, write %.1f); %.1f M voxels/s\n",
           (t_read + t_convert + t_write) * 1e3, t_read * 1e3, t_convert * 1e3, t_write * 1e3,
           t_convert > 0 ? vox / t_convert * 1e-6 : 0.0);
    printf("  peak memory  %s\n", vx_tool_bytes(vx_peak_rss()));
}

static int write_demo(const options* o) {
    vx_vox_scene s;
    vx_error err = {0};
    if (vx_demo_scene(NULL, &s) != VX_OK) return vx_tool_errorf("cannot build the demo scene: out of memory");
    vx_result r = vx_vox_write_file(&s, o->write_demo, &err);
    uint64_t voxels = 0;
    for (uint32_t i = 0; i < s.model_count; i++) voxels += s.models[i].voxel_count;
    if (r == VX_OK && !o->quiet)
        printf("%s: wrote demo scene %s: %u models, %u instances, %s voxels\n", vx_tool_name, o->write_demo,
               s.model_count, s.instance_count, vx_tool_num(voxels));
    vx_vox_scene_free(&s);
    return r == VX_OK ? 0 : vx_tool_error(o->write_demo, &err);
}

int main(int argc, char** argv) {
    vx_tool_init(argc, argv);
    options o = parse(argc, argv);
    if (o.write_demo) return write_demo(&o);

    vx_error err = {0};
    vx_logger log = vx_tool_logger(o.verbose);
    vx_progress prog = vx_tool_progress(o.quiet);
    vx_svo_build_desc build = {.no_collapse = o.no_collapse, .no_dag = o.no_dag, .progress = prog};
    vx_svo_scene scene;
    vx_conv_stats cs = {0};
    const char* ext = vx_tool_ext(o.in);
    const char* kind = ext;
    double t0 = vx_time_now(), t_read = 0, t_convert = 0;
    uint64_t in_bytes = 0;
    vx_result r;

    if (!strcmp(ext, "vox")) {
        kind = ".vox";
        vx_vox_scene vs;
        uint8_t* data = NULL;
        size_t size = 0;
        r = vx_file_read(o.in, NULL, 0, &data, &size, &err);
        if (r != VX_OK) return vx_tool_error(o.in, &err);
        in_bytes = size;
        vx_vox_read_desc rd = {.logger = &log, .frame = o.frame, .keep_hidden = o.keep_hidden};
        r = vx_vox_read(&rd, data, size, &vs, &err);
        free(data);
        if (r != VX_OK) return vx_tool_error(o.in, &err);
        t_read = vx_time_now() - t0;
        double t1 = vx_time_now();
        r = vx_conv_vox(&(vx_conv_vox_desc){.build = build}, &vs, &scene, &cs, &err);
        vx_vox_scene_free(&vs);
        if (r != VX_OK) return vx_tool_error(o.in, &err);
        t_convert = vx_time_now() - t1;
    } else if (!strcmp(ext, "gltf") || !strcmp(ext, "glb")) {
#ifdef VX_HAVE_MESH
        kind = !strcmp(ext, "glb") ? ".glb" : ".gltf";
        vx_conv_mesh_desc md = {.build = build, .logger = &log, .res = o.res, .scene_set = o.scene_set,
                                .scene = o.scene, .solid = o.solid, .normals = o.normals};
        r = vx_conv_mesh_file(&md, o.in, &scene, &cs, &err);
        vx_tool_progress_done();
        if (r != VX_OK) return vx_tool_error(o.in, &err);
        t_read = cs.seconds_read;
        t_convert = vx_time_now() - t0 - t_read;
#else
        return vx_tool_errorf("%s: this build has no glTF support", o.in);
#endif
    } else if (!strcmp(ext, "vdb")) {
#ifdef VX_HAVE_VDB
        kind = ".vdb";
        vx_conv_vdb_desc vd = {.build = build, .logger = &log, .grid = o.grid, .solid = o.solid,
                               .threshold_set = o.threshold_set, .threshold = o.threshold, .density = o.density,
                               .color_grid = o.color};
        r = vx_conv_vdb_file(&vd, o.in, &scene, &cs, &err);
        vx_tool_progress_done();
        if (r != VX_OK) return vx_tool_error(o.in, &err);
        t_read = cs.seconds_read;
        t_convert = vx_time_now() - t0 - t_read;
#else
        return vx_tool_errorf("%s: this build has no OpenVDB support", o.in);
#endif
    } else {
        return vx_tool_errorf("%s: unknown input type '.%s' (expected .vox, .gltf, .glb or .vdb)", o.in, ext);
    }
    vx_tool_progress_done();

    double t2 = vx_time_now();
    uint8_t* bytes = NULL;
    size_t nbytes = 0;
    r = vx_svo_write(&scene, NULL, &bytes, &nbytes, &err);
    if (r == VX_OK) r = vx_file_write_atomic(o.out, bytes, nbytes, &err);
    double t_write = vx_time_now() - t2;
    vx_svo_scene_free(&scene);
    vx_free(NULL, bytes);
    if (r != VX_OK) return vx_tool_error(o.out, &err);
    if (in_bytes == 0) {
        FILE* f = fopen(o.in, "rb");
        if (f) {
            fseek(f, 0, SEEK_END);
            long n = ftell(f);
            in_bytes = n > 0 ? (uint64_t)n : 0;
            fclose(f);
        }
    }
    print_stats(&o, kind, &cs, in_bytes, nbytes, t_read, t_convert, t_write);
    return 0;
}
