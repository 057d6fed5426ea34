/* tools/vox2svo/main.c - convert a MagicaVoxel scene, a glTF mesh or an
 * OpenVDB grid into a .svo file and print what the minimization did. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "convert/convert.h"
#include "tools/common/conv.h"
#include "tools/common/light.h"
#include "tools/common/tool.h"
#include "tools/vox2svo/demo.h"
#ifdef VX_HAVE_MESH_GPU
#include "convert/mesh_gpu.h"
#include "render/render.h"
#endif
#ifdef VX_HAVE_MPI
#include "tools/common/mpi.h"
#include "tools/vox2svo/mpi.h"
#endif

typedef struct options {
    const char* in;
    const char* out;
    const char* write_demo;
    uint32_t demo_frames; /* --demo-frames: an animated demo */
    bool quiet, verbose;
    bool gpu;          /* --gpu: meshes voxelized on the GPU */
    bool chunked;      /* --chunked: large models in the chunked form (format version 3) */
    bool chunk_fast;   /* --chunked-fast: the same with the node words stored (vx_write_desc.svo_chunk_fast) */
    bool chunk_deflate; /* --chunked-deflate: DEFLATE chunks, format version 3 (vx_write_desc.svo_chunk_deflate) */
    bool range_coded;   /* --range-coded: no split form, format version 1 or 2 (vx_write_desc.svo_range_coded) */
    const char* device; /* --device */
    bool sky_given;     /* --sky: stored in the output, replacing the input's */
    vx_sky sky;
    vx_tool_conv conv; /* reader and builder options */
} options;

static options default_options(void) {
    options o = {0};
    o.conv = vx_tool_conv_defaults();
    return o;
}

_Noreturn static void usage(int status) {
    options d = default_options();
    FILE* f = status == 0 ? stdout : stderr;
    fprintf(f,
            "Usage: %s IN.{vox,gltf,glb,vdb} OUT.svo [options]\n"
            "       %s 'smoke_####.vdb' OUT.svo   (a VDB sequence; also smoke_%%04d.vdb or a .txt list\n"
            "                                        of .vdb paths: one animation, unchanged bricks stored once)\n"
            "       %s --write-demo OUT.vox\n"
#ifdef VX_HAVE_MPI
            "       mpirun -n N %s MESH.{gltf,glb} OUT.svo [options]   (the regions split over the ranks)\n"
#endif
            "Which: converts a voxel scene, a triangle mesh or a volume into a compact sparse voxel\n"
            "       octree file (.svo): one Laine-Karras octree per model after tree minimization,\n"
            "       instances with their transforms. The reader is picked by the file extension;\n"
            "       .vox is MagicaVoxel's, or Teardown's variant (TDCZ voxel chunks, 255-entry RGBA).\n"
            "Lights and materials: glTF KHR_lights_punctual lights are stored (node transforms\n"
            "       applied; voxkit's record in a light's extras, as svo_info --to-glb writes it,\n"
            "       gives sphere and rect lights back exactly); glTF metallic, glass (KHR_materials_transmission, _ior) and emissive\n"
            "       materials and MagicaVoxel MATL materials are stored as MATL records. Emissive\n"
            "       voxels are not stored as lights: renderers derive one light per cluster\n"
            "       (svo_render --voxel-lights); the statistics count both.\n"
#ifdef VX_HAVE_MPI
            "Under MPI (mpirun -n N; this build has it): a glTF mesh's regions (the models of a mesh,\n"
            "       up to 2048^3 cells each) are split over the ranks, balanced by their surface bricks;\n"
            "       each rank voxelizes and builds its own regions' models (its memory: the mesh and\n"
            "       its share) and codes them into their streams of the file; rank 0 writes the streams\n"
            "       in order as they arrive, holding one at a time: the same bytes as one process.\n"
            "       Threads per rank: the host's CPUs over its ranks. -v prints per rank the regions,\n"
            "       voxels, read / convert / encode / send seconds, wall time and peak memory (emissive\n"
            "       voxels are not counted as lights under mpirun: the trees stay on their ranks). Other inputs:\n"
            "       one process.\n"
#endif
            "Options:\n"
            "    --frame N        one animation frame of a .vox scene (default: every frame, frame %u\n"
            "                     first; a static scene has one)\n"
            "    --keep-hidden    keep hidden nodes, groups and layers of a .vox scene\n"
            "    --keep-unused    keep the models of a .vox scene that no instance places\n"
            "                     (hidden shapes; with --frame, other frames; default: left out)\n"
            "    --no-collapse    skip minimization step 1 (uniform full subtrees -> one leaf)\n"
            "    --no-dag         skip minimization step 2 (share identical subtrees)\n"
            "    --res N          meshes: voxels along the longest side (default: %u)\n"
            "    --region N       meshes: cells per side of one model (a power of two from 64; default:\n"
            "                     one model up to 512 cells, beyond at least 8 models of at most 2048)\n"
            "    --scene N        meshes: glTF scene to convert (default: the file's default scene)\n"
            "    --solid          meshes and level sets: fill the inside, not only the surface\n"
            "    --normals        meshes: store oct-encoded normals\n"
#ifdef VX_HAVE_MESH_GPU
            "    --gpu            meshes: voxelize on the GPU (Vulkan, needs float64 shaders; the same\n"
            "                     cells, colours and file as the CPU path; with --solid the CPU fills\n"
            "                     the inside of the GPU's surface and builds); -v prints\n"
            "                     the GPU stages' times; under mpirun every rank voxelizes on the device\n"
            "                     and builds its share of the regions\n"
            "    --device D       with --gpu: the Vulkan device, an index or part of its name\n"
#endif
            "    --sky SPEC       store this sky in OUT.svo, replacing the input's (renderers use the\n"
            "                     file's sky unless given another; svo_render --sky's syntax; a map's\n"
            "                     FILE relative to the current folder is stored relative to OUT's;\n"
            "                     'default' stores none, dropping the input's):\n"
            "%s"
            "    --y-up           meshes: keep glTF's +Y up axis (default: turned to voxkit's +Z up,\n"
            "                     (x, y, z) -> (x, -z, y), so models stand upright as in MagicaVoxel)\n"
            "    --grid NAME      OpenVDB: grid to convert (default: the first scalar grid); where\n"
            "                     several grids share a name, NAME[N] is its N-th repeat (from 0)\n"
            "    --threshold X    OpenVDB fog volumes: keep active voxels with value >= X\n"
            "                     (default: any active value > 0)\n"
            "    --density        OpenVDB fog volumes: keep the values as a density attribute\n"
            "    --color NAME     OpenVDB: vec3 grid giving colours\n"
            "    --chunked        store models of 2^20 node words or more in the chunked form\n"
            "                     (zstd chunks, format version 4, docs/FORMAT.md 3.6): read and\n"
            "                     written on every core, 1.7-3x the bytes (the 4096^3 helmet on two\n"
            "                     cores: read 1.4-2.5 s, written 2.4-2.5 s, against 5.5-8.7 s and\n"
            "                     4.6-5.3 s); default: the compact structural forms\n"
            "    --chunked-deflate  as --chunked, DEFLATE chunks (format version 3, for readers\n"
            "                     before version 4): slower to write and read, slightly larger\n"
            "    --chunked-fast   as --chunked-deflate, the node words stored instead of deflated:\n"
            "                     faster than it, about 1.4x the bytes (version 3)\n"
            "    --range-coded    models of 2^20 node words or more in the range-coded form of\n"
            "                     versions 1 and 2 (for older readers) instead of the split form\n"
            "                     (format version 5, 6 with attributes, docs/FORMAT.md 3.7): slower\n"
            "                     to read and write\n"
            "    --max-memory SIZE  refuse an input that needs more memory than SIZE to read and\n"
            "                     convert (e.g. 512M, 4G; default: no limit; OpenVDB's and tinygltf's\n"
            "                     own memory is not counted)\n"
            "    --write-demo F   write the built-in demo scene (a .vox file) to F and exit\n"
            "    --demo-frames N  with --write-demo: an animation of N frames (the tower moves,\n"
            "                     four trees turn; default: the still scene)\n"
            "    -q, --quiet      print nothing but errors\n"
            "    -v, --verbose    print warnings and details\n"
            "    -h, --help       print this help and exit\n"
            "    --version        print the tool and format versions and exit\n"
            "Examples:\n"
            "    %s castle.vox castle.svo\n"
            "    %s --write-demo demo.vox && %s demo.vox demo.svo\n"
            "    %s DamagedHelmet.glb helmet.svo --res 1024\n"
            "    %s smoke.vdb smoke.svo --density\n",
            vx_tool_name, vx_tool_name, vx_tool_name,
#ifdef VX_HAVE_MPI
            vx_tool_name,
#endif
            d.conv.frame, d.conv.res, vx_tool_sky_syntax, vx_tool_name, vx_tool_name, vx_tool_name, vx_tool_name,
            vx_tool_name);
#ifdef VX_HAVE_MPI
    if (status && vx_tool_mpi_launched() && vx_tool_mpi_env_rank() > 0) vx_tool_mpi_linger(); /* rank 0 prints */
#endif
    exit(status);
}

#define usage_error(...) vx_tool_usage_error(usage, __VA_ARGS__)

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
        } else if (vx_tool_conv_option(argc, argv, &i, &o.conv, usage)) continue;
        else if (!strcmp(a, "--write-demo")) o.write_demo = vx_tool_arg(argc, argv, &i, usage);
        else if (!strcmp(a, "--chunked")) o.chunked = true;
        else if (!strcmp(a, "--chunked-fast")) o.chunked = o.chunk_fast = true;
        else if (!strcmp(a, "--chunked-deflate")) o.chunked = o.chunk_deflate = true;
        else if (!strcmp(a, "--range-coded")) o.range_coded = true;
#ifdef VX_HAVE_MESH_GPU
        else if (!strcmp(a, "--gpu")) o.gpu = true;
        else if (!strcmp(a, "--device")) o.device = vx_tool_arg(argc, argv, &i, usage);
#endif
        else if (!strcmp(a, "--sky")) {
            char why[160];
            if (!vx_tool_parse_sky(vx_tool_arg(argc, argv, &i, usage), true, &o.sky, why, sizeof why))
                usage_error("bad --sky '%s': %s", argv[i], why);
            o.sky_given = true;
        }
        else if (!strcmp(a, "--demo-frames")) {
            if (!vx_tool_parse_u32(vx_tool_arg(argc, argv, &i, usage), &o.demo_frames) || o.demo_frames > 4096)
                usage_error("bad --demo-frames value '%s' (0 to 4096)", argv[i]);
        }
        else if (!strcmp(a, "-q") || !strcmp(a, "--quiet")) o.quiet = true;
        else if (!strcmp(a, "-v") || !strcmp(a, "--verbose")) o.verbose = true;
        else if (a[0] == '-' && a[1]) usage_error("\"%s\" is not a valid option", a);
        else if (npos == 0) { o.in = a; npos++; }
        else if (npos == 1) { o.out = a; npos++; }
        else usage_error("unexpected argument '%s'", a);
    }
    if (o.write_demo) {
        if (npos) usage_error("%s", "--write-demo takes no other file arguments");
#ifdef VX_HAVE_MPI
        if (vx_tool_mpi_launched()) usage_error("%s", "--write-demo under mpirun: run it as one process");
#endif
        return o;
    }
    if (argc == 1) usage(2);
    if (npos != 2) usage_error("%s", "expected an input file and an output .svo file");
    if (o.device && !o.gpu) usage_error("%s", "--device goes with --gpu");
    if (o.gpu) {
        const char* k = vx_conv_file_kind(o.in);
        if (!k || (strcmp(k, ".gltf") && strcmp(k, ".glb"))) usage_error("--gpu: meshes only (.gltf, .glb), not %s", o.in);
    }
#ifdef VX_HAVE_MPI
    const char* kind = vx_conv_file_kind(o.in);
    if (vx_tool_mpi_launched() && (!kind || (strcmp(kind, ".gltf") && strcmp(kind, ".glb"))))
        usage_error("under mpirun only glTF meshes (.gltf, .glb) are split over the ranks; convert %s with one process",
                    o.in);
#endif
    return o;
}

static void print_stats(const options* o, const char* kind, const vx_conv_stats* cs, uint64_t in_bytes,
                        uint64_t out_bytes, double t_read, double t_convert, double t_write, uint32_t lights,
                        uint32_t voxel_lights) {
    if (o->quiet) return;
    const vx_svo_build_stats* b = &cs->build;
    double vox = b->voxels ? (double)b->voxels : 1.0;
    printf("%s: %s -> %s\n", vx_tool_name, o->in, o->out);
    printf("  input        %s, %s bytes\n", kind, vx_tool_num(in_bytes));
    printf("  voxels       %s (%s given)\n", vx_tool_num(b->voxels), vx_tool_num(b->input_voxels));
    printf("  models       %u, instances %u", cs->models, cs->instances);
    if (cs->frames > 1) printf(", frames %u", cs->frames);
    if (!strcmp(kind, ".vox"))
        printf(", unused models %s %u", o->conv.keep_unused ? "kept" : "left out", cs->models_unused);
    printf("\n");
    printf("  descriptors  plain %s -> collapsed %s -> dag %s", vx_tool_num(b->desc_plain),
           vx_tool_num(b->desc_collapsed), vx_tool_num(b->desc_dag));
    if (b->desc_plain)
        printf("  (%.1f%% of plain)", 100.0 * (double)b->desc_dag / (double)b->desc_plain);
    printf("\n");
    /* stored: glTF KHR_lights_punctual; from voxels: what a renderer derives (vx_svo_emissive_lights) */
    if (voxel_lights == UINT32_MAX)
        printf("  lights       %u stored; emissive voxels give more when rendering (-v counts them)\n", lights);
    else if (voxel_lights == UINT32_MAX - 1)
        printf("  lights       %u stored; emissive voxels give more when rendering (not counted under mpirun)\n", lights);
    else
        printf("  lights       %u stored, %u from emissive voxels (derived when rendering)\n", lights, voxel_lights);
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

/* The lights a renderer derives from the scene's emissive voxels, for the
 * statistics: counted only with -v where the scene has an emissive material
 * (clustering a textured mesh's emissive surface is slow: DamagedHelmet at
 * 2048 gives 395,544 clusters in minutes), else UINT32_MAX. */
static uint32_t count_voxel_lights(const vx_svo_scene* scene, bool verbose) {
    bool emissive = false;
    for (uint32_t i = 0; i < scene->material_count && !emissive; i++)
        emissive = vx_svo_material_resolve(&scene->materials[i]).emission > 0;
    if (!emissive) return 0;
    if (!verbose) return UINT32_MAX;
    uint32_t n = 0;
    vx_light* vl = NULL;
    vx_error err = {0};
    if (vx_svo_emissive_lights(scene, NULL, &vl, &n, &err) != VX_OK) n = 0;
    vx_free(NULL, vl);
    return n;
}

static int write_demo(const options* o) {
    vx_vox_scene s;
    vx_error err = {0};
    if (vx_demo_animation(NULL, o->demo_frames, &s) != VX_OK) return vx_tool_errorf("cannot build the demo scene: out of memory");
    vx_result r = vx_vox_write_file(NULL, &s, o->write_demo, &err);
    uint64_t voxels = 0;
    for (uint32_t i = 0; i < s.model_count; i++) voxels += s.models[i].voxel_count;
    if (r == VX_OK && !o->quiet)
        printf("%s: wrote demo scene %s: %u models, %u instances, %u frames, %s voxels\n", vx_tool_name, o->write_demo,
               s.model_count, s.instance_count, s.frame_count > 1 ? s.frame_count : 1, vx_tool_num(voxels));
    vx_vox_scene_free(&s);
    return r == VX_OK ? 0 : vx_tool_error(o->write_demo, &err);
}

#ifdef VX_HAVE_MPI
/* mpirun: rank 0 writes and prints what one process would; the other ranks
 * only convert their share (vox2svo_mpi) */
static int main_mpi(const options* opt) {
    options oc = *opt;
    const options* o = &oc;
    vx_svo_scene scene;
    vx_tool_loaded li;
#ifdef VX_HAVE_MESH_GPU
    /* --gpu: every rank voxelizes on its device (the one --device names, else
     * the first), then builds its share of the regions */
    vx_gpu* gpu = NULL;
    vx_conv_mesh_gpu* mg = NULL;
    if (oc.gpu) {
        vx_error e = {0};
        if (vx_gpu_create(&(vx_gpu_desc){.device = oc.device}, &gpu, &e) || vx_conv_mesh_gpu_create(gpu, NULL, &mg, &e))
            vx_tool_mpi_die("--gpu: %s", e.msg);
        oc.conv.mesh_backend = vx_conv_mesh_gpu_backend(mg);
    }
#endif
    vx_write_desc chunking = {.svo_chunk_words = o->chunked ? VX_SVO_CHUNK_WORDS : 0, .svo_chunk_fast = o->chunk_fast,
                             .svo_chunk_deflate = o->chunk_deflate, .svo_range_coded = o->range_coded};
    bool ok = vox2svo_mpi(o->in, &o->conv, &chunking, o->quiet, o->verbose, &scene, &li);
#ifdef VX_HAVE_MESH_GPU
    vx_conv_mesh_gpu_destroy(mg);
    vx_gpu_destroy(gpu);
#endif
    if (!ok) return 0;
    vx_error err = {0};
    if (o->sky_given) scene.sky = o->sky; /* its map's path is the current folder's (NULL below) */
    if (vx_sky_rebase(&scene.sky, o->sky_given ? NULL : o->in, o->out, &err) != VX_OK)
        vx_tool_mpi_die("%s: %s", o->out, err.msg);
    /* the trees stay on their ranks: emissive voxels are not clustered here */
    uint32_t lights = scene.light_count, voxel_lights = count_voxel_lights(&scene, false);
    if (voxel_lights == UINT32_MAX) voxel_lights = UINT32_MAX - 1;
    double t2 = vx_time_now();
    vx_result r = vox2svo_mpi_write(&scene, o->out, &err);
    double t_write = vx_time_now() - t2;
    vx_svo_scene_free(&scene);
    if (r != VX_OK) vx_tool_mpi_die("%s", err.msg); /* the message names the file; the other ranks end too */
    struct stat st;
    size_t nbytes = stat(o->out, &st) == 0 ? (size_t)st.st_size : 0;
    print_stats(o, li.kind, &li.stats, li.in_bytes, nbytes, li.seconds_read, li.seconds_total - li.seconds_read,
                t_write, lights, voxel_lights);
    fflush(stdout);
    vox2svo_mpi_end(t_write);
    return 0;
}
#endif

int main(int argc, char** argv) {
    vx_tool_init(argc, argv);
#ifdef VX_HAVE_MPI
    int saved[2];
    vx_tool_mpi_mute(saved); /* rank 0 alone prints usage errors */
    options o = parse(argc, argv);
    vx_tool_mpi_unmute(saved);
    if (vx_tool_mpi_launched()) return main_mpi(&o);
#else
    options o = parse(argc, argv);
#endif
    if (o.write_demo) return write_demo(&o);

    vx_error err = {0};
    vx_logger log = vx_tool_logger(o.verbose);
    vx_svo_scene scene;
    vx_tool_loaded li;
    vx_budget budget; /* --max-memory; outlives the scene */
    vx_budget_init(&budget, o.conv.max_memory, NULL);
    if (o.conv.max_memory) o.conv.alloc = &budget.allocator;
#ifdef VX_HAVE_MESH_GPU
    vx_gpu* gpu = NULL;
    vx_conv_mesh_gpu* mg = NULL;
    if (o.gpu) {
        if (vx_gpu_create(&(vx_gpu_desc){.device = o.device, .logger = &log}, &gpu, &err) ||
            vx_conv_mesh_gpu_create(gpu, o.conv.alloc, &mg, &err)) {
            vx_gpu_destroy(gpu);
            return vx_tool_errorf("--gpu: %s", err.msg);
        }
        o.conv.mesh_backend = vx_conv_mesh_gpu_backend(mg);
        if (o.verbose) fprintf(stderr, "%s: GPU voxelizer on %s\n", vx_tool_name, vx_gpu_device_name(gpu));
    }
#endif
    vx_result r = vx_tool_conv_load(o.in, &o.conv, false, &log, vx_tool_progress(o.quiet), &scene, &li, &err);
    vx_tool_progress_done();
#ifdef VX_HAVE_MESH_GPU
    if (mg && o.verbose && r == VX_OK) {
        vx_conv_mesh_gpu_stats gs;
        vx_conv_mesh_gpu_last_stats(mg, &gs);
        fprintf(stderr,
                "%s: GPU voxelizer: bin %.1f ms (CPU), upload %.1f, count %.1f, emit %.1f, sort %.1f (%u passes), "
                "reduce %.1f, tuples interned %.1f (%u passes), download %.1f, regions to the octree builder %.1f ms; "
                "%llu pairs, %llu pieces, %llu cells, %llu distinct tuples\n",
                vx_tool_name, gs.bin * 1e3, gs.upload * 1e3, gs.count * 1e3, gs.emit * 1e3, gs.sort * 1e3,
                gs.sort_passes, gs.reduce * 1e3, gs.intern * 1e3, gs.intern_passes, gs.download * 1e3, gs.sink * 1e3,
                (unsigned long long)gs.pairs, (unsigned long long)gs.records, (unsigned long long)gs.cells,
                (unsigned long long)gs.tuples);
    }
    vx_conv_mesh_gpu_destroy(mg);
    if (gpu) vx_gpu_destroy(gpu);
#endif
    if (r != VX_OK) return vx_tool_error_budget(o.in, &err, &budget);
    const char* kind = li.kind;
    const vx_conv_stats cs = li.stats;
    double t_read = li.seconds_read, t_convert = li.seconds_total - li.seconds_read;
    uint64_t in_bytes = li.in_bytes;

    /* a glTF's map sky names its image from the glTF's folder (formats/gltf.h),
     * a .svo's from the .svo's: the same image seen from the output's folder */
    if (o.sky_given) scene.sky = o.sky; /* its map's path is the current folder's (NULL below) */
    if (vx_sky_rebase(&scene.sky, o.sky_given ? NULL : o.in, o.out, &err) != VX_OK) {
        vx_svo_scene_free(&scene);
        return vx_tool_error(o.out, &err);
    }
    uint32_t lights = scene.light_count, voxel_lights = count_voxel_lights(&scene, o.verbose);
    double t2 = vx_time_now();
    /* streamed to disk: the file is never held in memory beside the scene */
    vx_write_desc wd = {.svo_chunk_words = o.chunked ? VX_SVO_CHUNK_WORDS : 0, .svo_chunk_fast = o.chunk_fast, .svo_chunk_deflate = o.chunk_deflate,
                        .svo_range_coded = o.range_coded};
    r = vx_svo_write_file(&wd, &scene, o.out, &err);
    double t_write = vx_time_now() - t2;
    vx_svo_scene_free(&scene);
    if (r != VX_OK) return vx_tool_errorf("%s", err.msg); /* the message names the file */
    struct stat st;
    size_t nbytes = stat(o.out, &st) == 0 ? (size_t)st.st_size : 0;
    print_stats(&o, kind, &cs, in_bytes, nbytes, t_read, t_convert, t_write, lights, voxel_lights);
    return 0;
}
