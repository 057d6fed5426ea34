/* tests/render/test_spirv_valid.c - every SPIR-V module the build embeds
 * passes the SPIR-V validator (spirv-val, Debian's spirv-tools) for the
 * environment glslangValidator compiles the kernels for. Twice a kernel
 * variant that glslang compiled was invalid (a `const bool` of `||` over
 * specialisation constants became an OpSpecConstantOp on an id that does not
 * dominate its uses: docs/PERFORMANCE.md, branches lean4 and ray8); lavapipe
 * ran it anyway, the NVIDIA driver crashed or failed the pipeline on the H200
 * and device time was lost. This test catches that on the dev machine.
 *
 * The modules are the embedded headers themselves (glslangValidator --vn
 * output, `0x...` words between the braces), listed by
 * tests/render/spirv_valid.cmake from the sources of every target, so a kernel
 * added anywhere is checked without editing this file. Each is written to a
 * temporary .spv and validated; the test fails naming each invalid module and
 * the validator's message, and skips when spirv-val is absent. With
 * arguments it checks those files instead (headers or .spv binaries), e.g. a
 * variant's kernel before it goes into a GPU payload.
 *
 * spirv-val on a module as compiled checks the default values of its
 * specialisation constants only, and a module can be valid so and invalid
 * once specialised (photons' zero-length array, docs/PERFORMANCE.md): so
 * test_specialised (ctest's test_spirv_specialised) specialises each module
 * with spirv-opt under the combinations the toolkit uses (spec_rows) and
 * validates each result, and test_control shows that check failing where it
 * must. Where the build has the toolkit's own specialiser (render/spirv_opt.h,
 * which lavapipe devices use: the constants frozen and the code they switch
 * off removed on the host), each combination's module from it is validated
 * too, and must declare no specialisation constant left. */
#define _POSIX_C_SOURCE 200809L /* popen, mkdtemp */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "render/spirv_opt.h"
#include "tests/test.h"

#include "spirv_modules.h" /* VX_SPIRV_VAL, VX_SPIRV_OPT, VX_SPIRV_ENV, VX_SPIRV_MODULES (tests/render/spirv_valid.cmake) */
#include "spec_control.comp.h" /* vx_test_spec_control_spv: shaders/spec_control.comp (test_control) */

static const char* const modules[] = {VX_SPIRV_MODULES NULL};
static int g_argc;
static char** g_argv;

/* The whole file, NUL-terminated, or NULL. */
static char* read_all(const char* path, size_t* len) {
    FILE* f = fopen(path, "rb");
    if (!f) return NULL;
    size_t cap = 1 << 16, n = 0;
    char* buf = malloc(cap);
    while (buf) {
        n += fread(buf + n, 1, cap - n - 1, f);
        if (n < cap - 1) break;
        char* nb = cap > (SIZE_MAX >> 2) ? NULL : realloc(buf, cap * 2);
        if (!nb) free(buf);
        buf = nb, cap *= 2;
    }
    if (ferror(f) && buf) free(buf), buf = NULL;
    fclose(f);
    if (buf) buf[n] = 0, *len = n;
    return buf;
}

/* The words of an embedded header (the hex literals between its first `{`
 * and the `}` after it) into a little-endian byte image in out; 0 and a
 * reason when the text is not such an array. */
static int header_words(const char* text, uint8_t** out, size_t* bytes, const char** why) {
    const char* p = strchr(text, '{');
    const char* end = p ? strchr(p, '}') : NULL;
    if (!p || !end) return *why = "no array between braces", 0;
    size_t cap = (size_t)(end - p) / 3 + 4, n = 0; /* each word takes at least "0x0," */
    uint8_t* b = malloc(cap * 4);
    if (!b) return *why = "out of memory", 0;
    for (p++; p < end;) {
        if (p[0] == '0' && (p[1] == 'x' || p[1] == 'X')) {
            char* q;
            unsigned long v = strtoul(p, &q, 16);
            if (q <= p + 2 || q > end || v > 0xFFFFFFFFul || n == cap) return free(b), *why = "bad word", 0;
            for (int k = 0; k < 4; k++) b[4 * n + k] = (uint8_t)(v >> (8 * k));
            n++, p = q;
        } else if (p[0] == ',' || p[0] == ' ' || p[0] == '\t' || p[0] == '\n' || p[0] == '\r') {
            p++;
        } else {
            return free(b), *why = "not a list of hex words", 0;
        }
    }
    if (n < 5 || b[0] != 0x03 || b[1] != 0x02 || b[2] != 0x23 || b[3] != 0x07)
        return free(b), *why = "no SPIR-V header (magic 0x07230203)", 0;
    *out = b, *bytes = 4 * n;
    return 1;
}

/* The module at path as a .spv file: an embedded header's words written to tmpdir/NAME (file gets that path), a
 * .spv file as it is (file gets path); 1, else 0 with the reason printed. */
static int module_file(const char* path, const char* tmpdir, const char* name, char* file, size_t file_size) {
    size_t len = 0;
    char* text = read_all(path, &len);
    if (!text) {
        fprintf(stderr, "  %s: cannot read (listed by the build but not built?)\n", path);
        return 0;
    }
    size_t plen = strlen(path);
    if (!(plen > 2 && !strcmp(path + plen - 2, ".h"))) {
        free(text);
        snprintf(file, file_size, "%s", path);
        return 1;
    }
    uint8_t* bytes = NULL;
    size_t nb = 0;
    const char* why = "";
    int ok = header_words(text, &bytes, &nb, &why);
    free(text);
    if (!ok) {
        fprintf(stderr, "  %s: not an embedded SPIR-V module: %s\n", path, why);
        return 0;
    }
    snprintf(file, file_size, "%s/%s", tmpdir, name);
    FILE* f = fopen(file, "wb");
    int wrote = f && fwrite(bytes, 1, nb, f) == nb;
    if (f && fclose(f)) wrote = 0;
    free(bytes);
    if (!wrote) fprintf(stderr, "  %s: cannot write %s\n", path, file);
    return wrote;
}

/* The output of a command started by popen (stdout and stderr, the first msg_size - 1 bytes) into msg; 1 when it
 * exited with status 0. */
static int finish_tool(FILE* p, char* msg, size_t msg_size) {
    msg[0] = 0;
    if (!p) return 0;
    size_t m = fread(msg, 1, msg_size - 1, p);
    msg[m] = 0;
    char rest[4096];
    while (fread(rest, 1, sizeof rest, p) > 0) {} /* the rest of a long message: read so the tool can exit */
    int st = pclose(p);
    return st != -1 && WIFEXITED(st) && WEXITSTATUS(st) == 0;
}

/* Runs cmd through the shell (finish_tool's msg and result). */
static int run_tool(const char* cmd, char* msg, size_t msg_size) {
    FILE* p = popen(cmd, "r");
    if (!p) return snprintf(msg, msg_size, "cannot start the shell"), 0;
    return finish_tool(p, msg, msg_size);
}

/* Validates one module (an embedded header, or a .spv file as it is), counted in *runs; 1 when
 * valid, else 0 with the reason (the validator's output) printed. */
static int validate(const char* path, const char* tmpdir, size_t* runs) {
    (*runs)++;
    char file[4096];
    if (!module_file(path, tmpdir, "module.spv", file, sizeof file)) return 0;
    /* the paths come from the build tree and the command line; quoted for the shell, a quote in them refused */
    if (strchr(file, '\'')) {
        fprintf(stderr, "  %s: a quote in the path\n", path);
        return 0;
    }
    char cmd[8192], msg[4096];
    snprintf(cmd, sizeof cmd, "'%s' --target-env %s '%s' 2>&1", VX_SPIRV_VAL, VX_SPIRV_ENV, file);
    int ok = run_tool(cmd, msg, sizeof msg);
    if (strcmp(file, path)) remove(file);
    if (!ok) fprintf(stderr, "  INVALID %s (spirv-val --target-env %s):\n%s\n", path, VX_SPIRV_ENV, msg);
    return ok;
}

/* Whether the tools were found when the build was configured: spirv-val, and spirv-opt where opt. */
static int tools_found(int opt) {
    return *VX_SPIRV_VAL && access(VX_SPIRV_VAL, X_OK) == 0 && (!opt || (*VX_SPIRV_OPT && access(VX_SPIRV_OPT, X_OK) == 0));
}

/* A fresh folder for a test's files in $TMPDIR (or /tmp), named after tag, into dir; 0 when it cannot be made. */
static int make_tmpdir(char* dir, size_t size, const char* tag) {
    const char* base = getenv("TMPDIR");
    snprintf(dir, size, "%s/vx_spirv_%s_XXXXXX", base && *base ? base : "/tmp", tag);
    return mkdtemp(dir) != NULL;
}

/* check (1: passed) on each module, the command line's files where given, else the build's; *n modules, *bad
 * failed; 0 when no folder for the files could be made. */
static int each_module(const char* tag, int (*check)(const char* path, const char* tmpdir, size_t* runs), size_t* runs,
                       int* n, int* bad) {
    char tmpdir[4096];
    if (!make_tmpdir(tmpdir, sizeof tmpdir, tag)) return 0;
    *n = *bad = 0;
    if (g_argc > 1) {
        for (int i = 1; i < g_argc; i++) (*n)++, *bad += !check(g_argv[i], tmpdir, runs);
    } else {
        for (const char* const* m = modules; *m; m++) (*n)++, *bad += !check(*m, tmpdir, runs);
    }
    rmdir(tmpdir);
    return 1;
}

static void test_modules_valid(void) {
    if (!tools_found(0))
        SKIP("spirv-val not found when the build was configured (Debian 12: spirv-tools; scripts/install-deps.sh)");
    int n, bad;
    size_t runs = 0;
    REQUIRE(each_module("valid", validate, &runs, &n, &bad));
    fprintf(stderr, "  %d modules, %d invalid\n", n, bad);
    CHECKF(n > 0, "no module to check");
    CHECKF(bad == 0, "%d of %d SPIR-V modules invalid (named above)", bad, n);
}

/* ---- the modules specialised ------------------------------------------------------------------------------ */

/* The values the toolkit gives each specialisation constant, from the C code that fills the pipelines'
 * VkSpecializationInfo (render/gpu_pipeline.c: ids 0..spec_count-1 from each desc, id 100 NODES_FILE from the
 * device). A row applies to the modules it lists (embedded headers' names, space-separated, or "*") and names the
 * constant by its OpName (glslang names each; "#ID" for one without a name, as photon.comp's workgroup size); the
 * first row that applies wins. A boolean without a row takes both values; an integer without one fails the test,
 * so a new integer constant gets its values here before it is checked. Values no pipeline is built with are only
 * an over-approximation (they must be valid too); values the code can give and the table leaves out are not
 * checked, so each row says where its values come from. */
typedef struct spec_row {
    const char* modules;
    const char* name;
    uint32_t n;
    uint32_t v[32];
} spec_row;
static const spec_row spec_rows[] = {
    /* trace_common.glsl's ids 0-4: the frame's mode and LOD in trace.comp (render_scene.c) and the compact kernel's
     * mode (compact_gpu.c); VX_RENDER_COLOR and LOD 0 in every kernel vx__render_scene_tables binds (the passes,
     * probes, cones, photons); the beam pass zeroes MODE, HAS_COLOR, LOD and WRITE_HITS (render_scene.c) */
    {"trace.comp.h trace_precise.comp.h trace_compact.comp.h", "MODE", 6, {0, 1, 2, 3, 4, 5}},
    {"trace.comp.h trace_precise.comp.h", "LOD", 2, {0, 1}},
    {"beam.comp.h", "HAS_COLOR", 1, {0}},
    {"beam.comp.h", "WRITE_HITS", 1, {0}},
    /* convert/mesh_gpu.c's pipes (before "*"'s MODE): meshvox, gpusort, gpuscan and meshreduce 0-1, meshintern
     * 0-3, meshbuild 0 to BUILD_MODES - 1 (31) */
    {"gpuscan.comp.h gpusort.comp.h meshreduce.comp.h meshvox.comp.h", "MODE", 2, {0, 1}},
    {"meshintern.comp.h", "MODE", 4, {0, 1, 2, 3}},
    {"meshbuild.comp.h",
     "MODE",
     31,
     {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19, 20, 21, 22, 23, 24, 25, 26, 27, 28, 29, 30}},
    {"*", "MODE", 1, {0}},
    {"*", "LOD", 1, {0}},
    /* DEEP (vx__render_scene_deep, compact_gpu.c; 0 in the float64 kernel); COMPACT_FORM (vx__render_scene_compact_form;
     * 0 in trace.comp and its beam pass: the compact layout has its own kernel) */
    {"trace_precise.comp.h", "DEEP", 1, {0}},
    {"*", "DEEP", 3, {0, 1, 2}},
    /* the grid walk's GRID (vx__render_scene_grid_spec: render_scene.c's grid_top, the greatest root level 1-3,
     * | 4 where every model with cells has a grid, | 8 where every root is at that level (2 or 3), | 16 the union
     * grid (with 4, and 8 at level 2 or 3), | 32 grids over their cells' cubes, | 64 the octant extents (a root at
     * least 64 wide); 0 none), in trace.comp and the pass kernels that trace (render/pipeline.c, pass_grid.glsl) */
    {"trace.comp.h gbuffer.comp.h direct.comp.h ao.comp.h frame.comp.h frame_display.comp.h", "GRID", 14,
     {0, 1, 2, 3, 5, 6, 7, 10, 14, 15, 21, 33, 65, 78}},
    {"trace.comp.h beam.comp.h", "COMPACT_FORM", 1, {0}},
    {"*", "COMPACT_FORM", 3, {0, 1, 2}},
    /* the beam's block side: render_scene.c's f->beam where over 1 (svo_render --beam), probe_gpu.c's BAKE_BEAM */
    {"probe.comp.h probe_one.comp.h probe_pt.comp.h probe_beam.comp.h", "BEAM", 2, {0, 4}},
    {"*", "BEAM", 4, {0, 2, 8, 16}},
    /* compact_gpu.c: the paged layout's page count; the attribute words' parts of 2^ATTR_SHIFT words (attr_parts) */
    {"trace_compact.comp.h", "PAGES", 4, {0, 1, 33, 100000}},
    {"trace_compact.comp.h", "ATTR_SHIFT", 3, {0, 20, 30}},
    /* probe_gpu.c probe_desc: the pass | 0x100 lights | 0x200 strata (the bake) | 0x400 glass and 0x800 metal (the
     * render passes) | the bake's bounces + 1 << 16; the bake's kernels pass 0, the render passes' (probe_pt) 1-6 */
    {"probe.comp.h probe_one.comp.h", "PCONST", 5, {0x0u, 0x10000u, 0x30100u, 0x90300u, 0xFF0200u}},
    {"probe_pt.comp.h", "PCONST", 10, {1, 2, 3, 4, 5, 6, 0x101, 0x106, 0x803, 0xD05}},
    /* pipeline.c: resolve's and the merged frame's inputs (bits 1-32), the intermediate shown (vx_show), the light
     * culling (0-2) | shadow slots (0-63) << 2 | emitters 0x100 in direct and the merged frame (0 elsewhere), post's op,
     * the light culling's steps */
    {"*", "FLAGS", 4, {0, 21, 42, 63}},
    {"*", "SHOW", 9, {0, 1, 2, 3, 4, 5, 6, 7, 8}},
    {"direct.comp.h frame.comp.h frame_display.comp.h", "LIGHTS", 5, {0, 0x005, 0x00A, 0x1FE, 0x100}},
    {"*", "LIGHTS", 1, {0}},
    {"*", "OP", 2, {0, 1}},
    {"cull.comp.h", "STEP", 5, {0, 1, 2, 3, 4}},
    /* cones.c: each shader's stages; the radiance's entries (1 or 6) | 16 specular | 32 shadows (the cone pass) */
    {"voxelize.comp.h inject.comp.h", "STAGE", 2, {0, 1}},
    {"filter.comp.h", "STAGE", 4, {0, 1, 2, 5}},
    {"cone.comp.h", "STAGE", 3, {0, 1, 2}},
    {"cone.comp.h", "CONE_SPEC", 4, {1, 6, 1 | 16 | 32, 6 | 16 | 32}},
    {"*", "CONE_SPEC", 2, {1, 6}},
    /* photons.c: the step (photon.comp's S_*: 0-7 and 9) and its workgroup (id 7: the trace's
     * vx_photon_desc.workgroup, default 32; the density step's 64 x 1, 4 or 8 lanes; else 64; 256 is left out: it
     * sizes the same arrays as 512, above 64 where the density step's big boxes start, and photon.comp is the
     * costliest module here); photons' zero-length density array (docs/PERFORMANCE.md) was invalid at STEP 7 with
     * 64 lanes and at every other step; photon_small.comp.h (the same without the trace and the camera's paths)
     * is made for steps 0, 2-4, 6, 7 and 9 (photons.c step) */
    {"photon.comp.h", "STEP", 9, {0, 1, 2, 3, 4, 5, 6, 7, 9}},
    {"photon_small.comp.h", "STEP", 7, {0, 2, 3, 4, 6, 7, 9}},
    {"photon.comp.h photon_small.comp.h", "#7", 3, {32, 64, 512}},
    /* bench/tree64.c's, bench/mipgrid.c's and bench/brickgrid.c's kernel variants; test_pipeline_cache's values; this
     * test's control (test_control) */
    {"tree64.comp.h brickgrid.comp.h", "SKIP", 2, {0, 1}},
    {"brickgrid.comp.h", "TOP", 3, {1, 2, 3}},
    {"brickgrid.comp.h", "FCOORD", 2, {0, 1}},
    {"mipgrid.comp.h", "PROBE", 3, {0, 1, 2}},
    {"cache_value.comp.h", "VALUE", 3, {0, 1, 3000}},
    {"spec_control.comp.h", "N", 1, {4}},
};

/* The names NAME of a space-separated list (or "*"): whether name is among them. */
static int in_list(const char* list, const char* name) {
    if (!strcmp(list, "*")) return 1;
    size_t n = strlen(name);
    for (const char* p = list; *p;) {
        while (*p == ' ') p++;
        const char* e = p;
        while (*e && *e != ' ') e++;
        if ((size_t)(e - p) == n && !strncmp(p, name, n)) return 1;
        p = e;
    }
    return 0;
}

/* One specialisation constant of a module: its id, whether boolean, its name, whether it reaches a type, and the
 * values it is checked with. */
typedef struct spec_const {
    uint32_t id, result; /* SpecId; the constant's result id */
    int is_bool;
    int typed; /* its value reaches an array's length or the workgroup size (through spec-constant operations) */
    char name[64];
    uint32_t n;
    const uint32_t* v;
} spec_const;
static const uint32_t bool_values[2] = {0, 1};

/* The specialisation constants of the module words w[0, nw) (OpDecorate SpecId on OpSpecConstant, True or False;
 * their OpName; whether each reaches a type), at most max; the count, or -1 when the words are not such a module. */
static int spec_consts(const uint32_t* w, size_t nw, spec_const* out, int max) {
    enum {
        OP_NAME = 5, OP_DECORATE = 71, OP_TYPE_ARRAY = 28, OP_SPEC_TRUE = 48, OP_SPEC_FALSE = 49, OP_SPEC = 50,
        OP_SPEC_COMPOSITE = 51, OP_SPEC_OP = 52, OP_EXECUTION_MODE_ID = 331, DEC_SPEC_ID = 1, DEC_BUILTIN = 11,
        BUILTIN_WORKGROUP_SIZE = 25, MODE_LOCAL_SIZE_ID = 38
    };
    if (nw < 5 || w[0] != 0x07230203u || w[3] > (1u << 22)) return -1;
    uint32_t bound = w[3];
    /* typed[id]: the id's value reaches a type; marked from the sinks, then back through the spec-constant
     * operations and composites (defined before their uses: one backward pass over the module reaches them all) */
    uint8_t* typed = calloc(bound ? bound : 1, 1);
    if (!typed) return -1;
    int n = 0, bad = 0;
    for (size_t i = 5; i < nw && !bad;) {
        uint32_t op = w[i] & 0xFFFFu, wc = w[i] >> 16;
        if (wc == 0 || i + wc > nw) {
            bad = 1;
            break;
        }
        if (op == OP_DECORATE && wc >= 4 && w[i + 2] == DEC_SPEC_ID && n < max)
            out[n++] = (spec_const){.id = w[i + 3], .result = w[i + 1], .is_bool = -1};
        if (op == OP_DECORATE && wc >= 4 && w[i + 2] == DEC_BUILTIN && w[i + 3] == BUILTIN_WORKGROUP_SIZE &&
            w[i + 1] < bound)
            typed[w[i + 1]] = 1;
        if (op == OP_TYPE_ARRAY && wc >= 4 && w[i + 3] < bound) typed[w[i + 3]] = 1;
        if (op == OP_EXECUTION_MODE_ID && wc >= 6 && w[i + 2] == MODE_LOCAL_SIZE_ID)
            for (uint32_t k = 3; k < 6; k++)
                if (w[i + k] < bound) typed[w[i + k]] = 1;
        i += wc;
    }
    /* the instructions' starts, to walk them backwards */
    size_t cap = nw / 2 + 1, ni = 0;
    uint32_t* at = bad ? NULL : malloc(cap * sizeof *at);
    for (size_t i = 5; at && i < nw && ni < cap; i += w[i] >> 16) at[ni++] = (uint32_t)i;
    for (size_t j = ni; j-- > 0;) {
        uint32_t i = at[j], op = w[i] & 0xFFFFu, wc = w[i] >> 16;
        if ((op != OP_SPEC_OP && op != OP_SPEC_COMPOSITE) || wc < 3 || w[i + 2] >= bound || !typed[w[i + 2]]) continue;
        for (uint32_t k = op == OP_SPEC_OP ? 4 : 3; k < wc; k++)
            if (w[i + k] < bound) typed[w[i + k]] = 1;
    }
    if (!at) bad = 1;
    free(at);
    /* the names and kinds by result id */
    for (size_t i = 5; !bad && i < nw;) {
        uint32_t op = w[i] & 0xFFFFu, wc = w[i] >> 16;
        for (int k = 0; k < n; k++) {
            if (op == OP_NAME && wc >= 3 && w[i + 1] == out[k].result) {
                size_t len = (wc - 2) * 4;
                const char* str = (const char*)&w[i + 2];
                size_t m = strnlen(str, len);
                if (m >= sizeof out[k].name) m = sizeof out[k].name - 1;
                memcpy(out[k].name, str, m), out[k].name[m] = 0;
            }
            if ((op == OP_SPEC_TRUE || op == OP_SPEC_FALSE) && wc >= 3 && w[i + 2] == out[k].result) out[k].is_bool = 1;
            if (op == OP_SPEC && wc >= 4 && w[i + 2] == out[k].result) out[k].is_bool = 0;
        }
        i += wc;
    }
    for (int k = 0; !bad && k < n; k++) {
        if (out[k].is_bool < 0 || out[k].result >= bound) bad = 1; /* a SpecId on something else */
        else out[k].typed = typed[out[k].result];
        if (!out[k].name[0]) snprintf(out[k].name, sizeof out[k].name, "#%u", out[k].id);
    }
    free(typed);
    return bad ? -1 : n;
}

/* The combinations to check: every pair of values of two constants that reach a type (the only ones whose values
 * can change what spirv-val finds: once frozen, a constant in code is an operand like any other, while a type's
 * array length must be at least 1) in some row, and every value of every constant in some row (greedy: each row
 * starts from the first pair, else value, not yet covered and gives each other constant the value that covers the
 * most new ones); at least one row; rows[r * nc + k] is constant k's value index in row r. The count, or 0 without
 * memory. */
static size_t pair_rows(const spec_const* c, int nc, uint32_t** rows_out) {
    if (nc < 0 || nc > 64) return 0;
    /* pairs[k][l] for typed k < l: an n_k x n_l grid of flags; once[k]: a flag per value */
    uint8_t* pairs[64][64] = {{0}};
    uint8_t* once[64] = {0};
    size_t left = 0, cap = 16, nr = 0;
    uint32_t* rows = NULL;
    int nomem = 0;
    for (int k = 0; k < nc && !nomem; k++) {
        nomem |= !(once[k] = calloc(c[k].n ? c[k].n : 1, 1));
        left += c[k].n;
        for (int l = k + 1; l < nc && !nomem && c[k].typed; l++) {
            if (!c[l].typed) continue;
            nomem |= !(pairs[k][l] = calloc((size_t)c[k].n * c[l].n, 1));
            left += (size_t)c[k].n * c[l].n;
        }
    }
    rows = nomem ? NULL : malloc(cap * (size_t)(nc ? nc : 1) * sizeof *rows);
    if (!rows) nomem = 1;
    if (!nomem && nc == 0) nr = 1; /* the one row: the defaults */
    while (!nomem && left) {
        if (nr == cap) {
            uint32_t* r = realloc(rows, 2 * cap * (size_t)nc * sizeof *rows);
            if (!r) {
                nomem = 1;
                break;
            }
            rows = r, cap *= 2;
        }
        uint32_t* row = rows + nr * (size_t)nc;
        int set[64] = {0}, found = 0;
        for (int k = 0; k < nc && !found; k++)
            for (int l = k + 1; l < nc && !found; l++)
                for (uint32_t a = 0; pairs[k][l] && a < c[k].n && !found; a++)
                    for (uint32_t b = 0; b < c[l].n && !found; b++)
                        if (!pairs[k][l][a * c[l].n + b]) row[k] = a, row[l] = b, set[k] = set[l] = found = 1;
        for (int k = 0; k < nc && !found; k++)
            for (uint32_t a = 0; a < c[k].n && !found; a++)
                if (!once[k][a]) row[k] = a, set[k] = found = 1;
        for (int k = 0; k < nc; k++) {
            if (set[k]) continue;
            uint32_t best = 0;
            size_t best_new = 0;
            for (uint32_t a = 0; a < c[k].n; a++) {
                size_t fresh = !once[k][a];
                for (int l = 0; l < nc; l++) {
                    if (!set[l]) continue;
                    if (l < k && pairs[l][k]) fresh += !pairs[l][k][row[l] * c[k].n + a];
                    if (l > k && pairs[k][l]) fresh += !pairs[k][l][a * c[l].n + row[l]];
                }
                if (fresh > best_new) best = a, best_new = fresh;
            }
            row[k] = best, set[k] = 1;
        }
        for (int k = 0; k < nc; k++) {
            left -= !once[k][row[k]], once[k][row[k]] = 1;
            for (int l = k + 1; l < nc; l++)
                if (pairs[k][l]) {
                    uint8_t* f = &pairs[k][l][row[k] * c[l].n + row[l]];
                    left -= !*f, *f = 1;
                }
        }
        nr++;
    }
    for (int k = 0; k < nc; k++) {
        free(once[k]);
        for (int l = k + 1; l < nc; l++) free(pairs[k][l]);
    }
    if (nomem) {
        free(rows);
        return 0;
    }
    *rows_out = rows;
    return nr;
}

/* The toolkit's own specialisation (render/spirv_opt.h) of the module words w[0, nw) with the values of row into
 * tmpdir/host_SLOT.spv: 1 when written (and it declares no constant left: spec_consts finds none), else 0 with the
 * reason in msg. */
static int host_specialise(const uint32_t* w, size_t nw, const char* tmpdir, int slot, const spec_const* c, int nc,
                           const uint32_t* row, char* msg, size_t msg_size) {
    uint32_t ids[64], vals[64];
    if (nc > 64) return snprintf(msg, msg_size, "%d constants", nc), 0;
    for (int k = 0; k < nc; k++) ids[k] = c[k].id, vals[k] = c[k].v[row[k]];
    uint32_t* out = NULL;
    size_t nout = 0;
    vx_error err = {0};
    spec_const left[1];
    int ok = 1;
    if (vx__spirv_specialise(w, nw, ids, vals, (uint32_t)nc, &out, &nout, &err))
        ok = 0, snprintf(msg, msg_size, "vx__spirv_specialise: %s", err.msg);
    if (ok && spec_consts(out, nout, left, 1) != 0) ok = 0, snprintf(msg, msg_size, "a specialisation constant is left");
    if (ok) {
        char file[4200];
        snprintf(file, sizeof file, "%s/host_%d.spv", tmpdir, slot);
        FILE* f = fopen(file, "wb");
        ok = f && fwrite(out, 4, nout, f) == nout;
        if (f && fclose(f)) ok = 0;
        if (!ok) snprintf(msg, msg_size, "cannot write host_%d.spv in the test folder", slot);
    }
    free(out);
    return ok;
}

/* Starts specialising the module spv with the values of row and validating the result (finish_tool reads the
 * outcome: 1 when valid, else 0 with the tools' output): spirv-opt sets the constants' defaults, freezes them into
 * constants and folds what depends on them (as a driver's specialisation does) into tmpdir/special_SLOT.spv, which
 * spirv-val checks; where host (host_specialise wrote tmpdir/host_SLOT.spv) spirv-val checks that one too. NULL when
 * the command cannot start. */
static FILE* specialise_start(const char* spv, const char* tmpdir, int slot, const spec_const* c, int nc,
                              const uint32_t* row, int host) {
    char vals[2048] = "", cmd[8192], host_check[4400] = "";
    if (host)
        snprintf(host_check, sizeof host_check, " && '%s' --target-env %s '%s/host_%d.spv' 2>&1", VX_SPIRV_VAL,
                 VX_SPIRV_ENV, tmpdir, slot);
    size_t o = 0;
    for (int k = 0; k < nc && o < sizeof vals; k++) {
        uint32_t v = c[k].v[row[k]];
        /* spirv-opt reads a boolean's value as true or false only (it ignores 1 without a word) */
        if (c[k].is_bool)
            o += (size_t)snprintf(vals + o, sizeof vals - o, "%s%u:%s", k ? " " : "", c[k].id, v ? "true" : "false");
        else
            o += (size_t)snprintf(vals + o, sizeof vals - o, "%s%u:%u", k ? " " : "", c[k].id, v);
    }
    snprintf(cmd, sizeof cmd,
             "'%s' --target-env=%s --set-spec-const-default-value '%s' --freeze-spec-const --fold-spec-const-op-composite "
             "'%s' -o '%s/special_%d.spv' 2>&1 && '%s' --target-env %s '%s/special_%d.spv' 2>&1%s; r=$?; "
             "rm -f '%s/special_%d.spv' '%s/host_%d.spv'; exit $r",
             VX_SPIRV_OPT, VX_SPIRV_ENV, vals, spv, tmpdir, slot, VX_SPIRV_VAL, VX_SPIRV_ENV, tmpdir, slot, host_check,
             tmpdir, slot, tmpdir, slot);
    return popen(cmd, "r");
}

/* specialise_start and finish_tool in one. */
static int specialise(const char* spv, const uint32_t* w, size_t nw, const char* tmpdir, const spec_const* c, int nc,
                      const uint32_t* row, char* msg, size_t msg_size) {
    int host = vx__spirv_can_specialise();
    if (host && !host_specialise(w, nw, tmpdir, 0, c, nc, row, msg, msg_size)) return 0;
    return finish_tool(specialise_start(spv, tmpdir, 0, c, nc, row, host), msg, msg_size);
}

/* Checks module path under its combinations (pair_rows over spec_rows' values); adds the combinations checked to
 * *runs; 1 when all are valid (a module without constants has none: test_modules_valid checks it as it is). The
 * failing combinations are printed with the tools' message; a module stops after three (its last batch ends). */
static int check_specialised(const char* path, const char* tmpdir, size_t* runs) {
    const char* base = strrchr(path, '/');
    base = base ? base + 1 : path;
    char file[4096];
    if (!module_file(path, tmpdir, "module.spv", file, sizeof file)) return 0;
    if (strchr(file, '\'') || strchr(tmpdir, '\'')) return fprintf(stderr, "  %s: a quote in the path\n", path), 0;
    size_t len = 0;
    char* bytes = read_all(file, &len);
    spec_const c[64];
    int nc = -1;
    /* the module's words, kept for the host's specialisation of each combination */
    uint32_t* w = bytes && len % 4 == 0 ? malloc(len ? len : 4) : NULL;
    if (w) memcpy(w, bytes, len), nc = spec_consts(w, len / 4, c, 64);
    free(bytes);
    int ok = nc >= 0;
    if (!ok) fprintf(stderr, "  %s: its specialisation constants could not be read\n", path);
    for (int k = 0; ok && k < nc; k++) {
        const spec_row* r = NULL;
        for (size_t i = 0; !r && i < sizeof spec_rows / sizeof spec_rows[0]; i++)
            if (!strcmp(spec_rows[i].name, c[k].name) && in_list(spec_rows[i].modules, base)) r = &spec_rows[i];
        if (r) c[k].n = r->n, c[k].v = r->v;
        else if (c[k].is_bool) c[k].n = 2, c[k].v = bool_values;
        else ok = 0, fprintf(stderr, "  %s: integer constant %s (id %u) has no values in spec_rows\n", base, c[k].name, c[k].id);
    }
    uint32_t* rows = NULL;
    size_t nr = ok && nc > 0 ? pair_rows(c, nc, &rows) : 0;
    if (ok && nc > 0 && !nr) ok = 0, fprintf(stderr, "  %s: out of memory\n", base);
    /* JOBS combinations at a time (the machine's cores, at most 4: CI has 2), each its own pair of processes */
    enum { JOBS_MAX = 4 };
    long cores = sysconf(_SC_NPROCESSORS_ONLN);
    size_t jobs = cores < 1 ? 1 : cores > JOBS_MAX ? JOBS_MAX : (size_t)cores;
    int bad = 0;
    for (size_t r0 = 0; ok && r0 < nr && bad < 3; r0 += jobs) {
        FILE* p[JOBS_MAX] = {NULL};
        char host_msg[JOBS_MAX][256];
        int host_ok[JOBS_MAX];
        size_t nj = nr - r0 < jobs ? nr - r0 : jobs;
        int host = vx__spirv_can_specialise();
        for (size_t j = 0; j < nj; j++) {
            const uint32_t* row = rows + (r0 + j) * (size_t)nc;
            host_ok[j] = !host || host_specialise(w, len / 4, tmpdir, (int)j, c, nc, row, host_msg[j], sizeof host_msg[j]);
            p[j] = host_ok[j] ? specialise_start(file, tmpdir, (int)j, c, nc, row, host) : NULL;
        }
        for (size_t j = 0; j < nj; j++) {
            char msg[4096];
            (*runs)++;
            if (!host_ok[j]) snprintf(msg, sizeof msg, "%s", host_msg[j]);
            if (host_ok[j] && finish_tool(p[j], msg, sizeof msg)) continue;
            bad++;
            fprintf(stderr, "  INVALID %s specialised with", base);
            for (int k = 0; k < nc; k++) fprintf(stderr, " %s=%u", c[k].name, c[k].v[rows[(r0 + j) * (size_t)nc + k]]);
            fprintf(stderr, ":\n%s\n", p[j] || !host_ok[j] ? msg : "(the tools could not be started)");
        }
    }
    if (ok && nc > 0) {
        fprintf(stderr, "  %-24s %2d constants, %3zu combinations%s; reaching a type:", base, nc, nr, bad ? ", INVALID" : "");
        for (int k = 0; k < nc; k++)
            if (c[k].typed) fprintf(stderr, " %s", c[k].name);
        fprintf(stderr, "\n");
    }
    free(rows);
    free(w);
    if (strcmp(file, path)) remove(file);
    return ok && !bad;
}

/* Every embedded module under the specialisation constants' combinations the toolkit uses (spec_rows, pair_rows).
 * spirv-val on the module as compiled checks the defaults only: a module can be valid so and invalid once
 * specialised (photons' zero-length array, docs/PERFORMANCE.md). */
static void test_specialised(void) {
    if (!tools_found(1)) SKIP("spirv-val or spirv-opt not found when the build was configured (Debian 12: spirv-tools)");
    int n, bad;
    size_t runs = 0;
    REQUIRE(each_module("spec", check_specialised, &runs, &n, &bad));
    fprintf(stderr, "  %d modules, %zu specialised modules validated, %d modules failed\n", n, runs, bad);
    CHECKF(n > 0, "no module to check");
    CHECKF(bad == 0, "%d of %d SPIR-V modules invalid once specialised or not checked (named above)", bad, n);
}

/* The check itself can fail: the control kernel (shaders/spec_control.comp) declares an array of N - 1 elements
 * where B holds; specialised with N 1 and B true it is invalid, with B false (a boolean spirv-opt must read) or N 4
 * valid. */
static void test_control(void) {
    if (!tools_found(1)) SKIP("spirv-val or spirv-opt not found when the build was configured (Debian 12: spirv-tools)");
    char tmpdir[4096], file[4200];
    REQUIRE(make_tmpdir(tmpdir, sizeof tmpdir, "ctl"));
    snprintf(file, sizeof file, "%s/control.spv", tmpdir);
    FILE* f = fopen(file, "wb");
    int wrote = f && fwrite(vx_test_spec_control_spv, 1, sizeof vx_test_spec_control_spv, f) == sizeof vx_test_spec_control_spv;
    if (f && fclose(f)) wrote = 0;
    REQUIRE(wrote);
    spec_const c[4];
    const uint32_t* cw = vx_test_spec_control_spv;
    size_t cn = sizeof vx_test_spec_control_spv / 4;
    int nc = spec_consts(cw, cn, c, 4);
    REQUIRE(nc == 2);
    int in = !strcmp(c[0].name, "N") ? 0 : 1, ib = 1 - in;
    CHECK(!strcmp(c[in].name, "N") && !c[in].is_bool && c[in].id == 0);
    CHECK(!strcmp(c[ib].name, "B") && c[ib].is_bool == 1 && c[ib].id == 1);
    static const uint32_t vals[] = {1, 4, 0, 1};
    c[in].v = vals, c[in].n = 2, c[ib].v = vals + 2, c[ib].n = 2;
    uint32_t row[2];
    char msg[4096];
    row[in] = 0, row[ib] = 1; /* N 1, B true: an array of length 0 */
    CHECKF(!specialise(file, cw, cn, tmpdir, c, nc, row, msg, sizeof msg), "N 1, B true passed");
    CHECKF(strstr(msg, "at least 1") != NULL, "N 1, B true: not the zero-length array: %s", msg);
    row[in] = 0, row[ib] = 0; /* N 1, B false */
    CHECKF(specialise(file, cw, cn, tmpdir, c, nc, row, msg, sizeof msg), "N 1, B false: %s", msg);
    row[in] = 1, row[ib] = 1; /* N 4, B true */
    CHECKF(specialise(file, cw, cn, tmpdir, c, nc, row, msg, sizeof msg), "N 4, B true: %s", msg);
    /* both reach the array's length */
    CHECK(c[in].typed && c[ib].typed);
    /* the rows: every pair of values of the three constants that reach a type (3, 2 and 2 values) in some row, and
     * every value of the fourth (5 values, no type) */
    spec_const p[4] = {{.n = 3, .typed = 1}, {.n = 2, .typed = 1}, {.n = 2, .typed = 1}, {.n = 5}};
    uint32_t* rows = NULL;
    size_t nr = pair_rows(p, 4, &rows);
    REQUIRE(nr >= 6 && rows);
    for (int k = 0; k < 3; k++)
        for (int l = k + 1; l < 3; l++)
            for (uint32_t a = 0; a < p[k].n; a++)
                for (uint32_t b = 0; b < p[l].n; b++) {
                    int seen = 0;
                    for (size_t r = 0; r < nr; r++) seen |= rows[r * 4 + k] == a && rows[r * 4 + l] == b;
                    CHECKF(seen, "pair (%d=%u, %d=%u) in no row", k, a, l, b);
                }
    for (uint32_t a = 0; a < p[3].n; a++) {
        int seen = 0;
        for (size_t r = 0; r < nr; r++) seen |= rows[r * 4 + 3] == a;
        CHECKF(seen, "value %u of the fourth constant in no row", a);
    }
    CHECKF(nr <= 8, "%zu rows for 6 pairs of the first two and 5 values", nr);
    free(rows);
    remove(file);
    rmdir(tmpdir);
}

/* The parser itself: a header's words come out little-endian, and text that
 * is not such an array is refused, not read past. */
static void test_header_parse(void) {
    uint8_t* b = NULL;
    size_t nb = 0;
    const char* why = "";
    REQUIRE(header_words("const uint32_t a[] = {\n\t0x07230203,0x00010300,0x0008000b,0x1,0xFFFFFFFF\n};", &b, &nb, &why));
    CHECK(nb == 20);
    CHECK(b[0] == 0x03 && b[3] == 0x07 && b[4] == 0x00 && b[6] == 0x01 && b[12] == 0x01 && b[19] == 0xFF);
    free(b);
    CHECK(!header_words("const uint32_t a[] = {0x07230203,0x1};", &b, &nb, &why));        /* too short */
    CHECK(!header_words("const uint32_t a[] = {0x12345678,0,0,0,0};", &b, &nb, &why));    /* no magic */
    CHECK(!header_words("{0x07230203,0x1,0x2,0x3,0x4,foo}", &b, &nb, &why));              /* junk */
    CHECK(!header_words("{0x07230203,0x1,0x2,0x3,0x1FFFFFFFF}", &b, &nb, &why));          /* over 32 bits */
    CHECK(!header_words("{0x07230203,0x1,0x2,0x3,0x4", &b, &nb, &why));                   /* unclosed */
    CHECK(!header_words("", &b, &nb, &why));
}

int main(int argc, char** argv) {
    g_argc = argc, g_argv = argv;
    RUN(test_header_parse);
    RUN(test_modules_valid);
    RUN(test_control);
    RUN(test_specialised);
    return vx_test_finish();
}
