/* tests/render/test_spirv_precise.c - the float walk's error-free
 * transformations (issue 18: the hi/lo origin of the DEEP kernels, the
 * two-sums and exact products in trace_instance and trace_model) must reach
 * the driver as arithmetic decorated NoContraction. Where an operation of
 * such a sum is not (GLSL `precise` missing on the variable it feeds), the
 * driver may apply exact algebra to it: the NVIDIA compiler (driver 580)
 * folded the instance two-sum's error term (dt - (s - bb)) + (w - bb) to 0,
 * and 380 of 110,592 depth-16 close-up pixels left the CPU reference on the
 * H200, while lavapipe, which does not fold, passed. No lavapipe render can
 * see that, so this test reads the embedded SPIR-V: every float operation in
 * the expression stored into one of those variables (up to the loads of
 * other variables, whose own stores are checked when they are in the list)
 * carries NoContraction. With arguments, checks those .spv files instead
 * (e.g. a kernel built from main before the fix, which must fail).
 *
 * The GPU path tracer (probes/shaders/probe.comp, its render kernel) is
 * checked whole: with the sun's depth map (SMAP) and without it, the NVIDIA
 * compiler contracted the path's float operations differently, and 54 of
 * 2,073,600 values of a Cornell box image differed (issue 21, H200), while
 * lavapipe gave the same bits. So every float operation of the functions that
 * decide an image's value (camera ray, hit point and normal, sampling, BSDF,
 * lights, sky, accumulation, and the octree walk: with the path alone precise
 * 45 values still differed) must carry NoContraction there, not only those
 * feeding some variables. `test_spirv_precise --path FILE.spv` checks a
 * kernel file that way (main's probe.comp before the fix: 475 fail).
 *
 * The kernels of cmake/shaders.cmake's VX_WALK_PRECISE_KERNELS (the list
 * reaches this test as a define of the same name: the pass pipeline's
 * G-buffer, direct, AO and merged kernels, the cones' kernels, the photons')
 * are built with WALK_PRECISE: with a contractible walk the NVIDIA compiler
 * contracted the walk's crossing times differently in the plain and the
 * compact layout's pipelines (the COMPACT constant), and 5 of
 * test_compact_passes' room hits came out one float step apart in depth, its
 * cone gi and its frame-lit direct light with them (issue 18, H200; lavapipe
 * gave the same bits). So every float operation of their walk (trace_model,
 * trace_instance, box_t, safe_inv) and of the secondary rays' start
 * (gb_offset_point, where the kernel has it) must carry NoContraction; a
 * listed name this test cannot find fails; trace.comp, built without it,
 * must not (the control). */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tests/test.h"

#include "trace.comp.h"
#include "trace_compact.comp.h"
#include "ao.comp.h"
#include "direct.comp.h"
#include "frame.comp.h"
#include "frame_display.comp.h"
#include "gbuffer.comp.h"
#ifdef VX_TEST_CONES
#include "cone.comp.h"
#include "inject.comp.h"
#include "voxelize.comp.h"
#endif
#ifdef VX_TEST_PROBES
#include "probe.comp.h"
#include "probe_pt.comp.h"
#include "probe_one.comp.h"
#endif
#ifdef VX_TEST_PHOTONS
#include "photon.comp.h"
#endif
#ifndef VX_WALK_PRECISE_KERNELS
#error "VX_WALK_PRECISE_KERNELS (cmake/shaders.cmake) not defined"
#endif

enum {
    OP_EXT_INST = 12, OP_NAME = 5, OP_FUNCTION = 54, OP_FUNCTION_END = 56, OP_VARIABLE = 59, OP_LOAD = 61,
    OP_STORE = 62, OP_DECORATE = 71, OP_VECTOR_SHUFFLE = 79, OP_COMPOSITE_CONSTRUCT = 80,
    OP_COMPOSITE_EXTRACT = 81, OP_COMPOSITE_INSERT = 82, OP_FNEGATE = 127, OP_FADD = 129, OP_FSUB = 131,
    OP_FMUL = 133, OP_FDIV = 136, OP_FREM = 140, OP_FMOD = 141, OP_VECTOR_TIMES_SCALAR = 142,
    OP_MATRIX_TIMES_SCALAR = 143, OP_VECTOR_TIMES_MATRIX = 144, OP_MATRIX_TIMES_VECTOR = 145, OP_DOT = 148, OP_SELECT = 169,
    DEC_NO_CONTRACTION = 42
};

/* The variables of each function that hold an error-free transformation's
 * parts (render/shaders/trace_common.glsl and trace_compact.comp: the
 * DEEP 2 set-up's oa + oa_lo and ol + ol_lo, the rebase's q, the instance's
 * om + om_lo). */
static const char* const model_vars[] = {"pr", "pe", "oas", "bb", "se", "oal", "ols", "oll", "a", "sq", "q", NULL};
static const char* const inst_vars[] = {"s", "bb", "om_lo", NULL};

typedef struct spv {
    const uint32_t* w;
    size_t n;
    uint32_t bound;
    uint32_t* def;   /* id -> word index of its defining instruction (0: none) */
    uint8_t* nocon;  /* id decorated NoContraction */
    uint32_t* name;  /* id -> word index of its OpName string (0: none) */
    uint32_t* func;  /* variable id -> its function's id */
    uint8_t* seen;
} spv;

static void str_at(const spv* m, uint32_t at, char* out, size_t cap) {
    size_t k = 0;
    for (uint32_t i = at; i < m->n && k + 1 < cap; i++)
        for (int b = 0; b < 4 && k + 1 < cap; b++) {
            char c = (char)((m->w[i] >> (8 * b)) & 0xFFu);
            if (!c) goto done;
            out[k++] = c;
        }
done:
    out[k] = 0;
}

static int name_is(const spv* m, uint32_t id, const char* s) {
    if (id >= m->bound || !m->name[id]) return 0;
    char buf[128];
    str_at(m, m->name[id], buf, sizeof buf);
    return !strcmp(buf, s);
}

/* The instructions read below (all have a result type and a result id). */
static int has_result(uint32_t op) {
    switch (op) {
    case OP_EXT_INST: case OP_VARIABLE: case OP_LOAD: case OP_VECTOR_SHUFFLE: case OP_COMPOSITE_CONSTRUCT:
    case OP_COMPOSITE_EXTRACT: case OP_COMPOSITE_INSERT: case OP_FNEGATE: case OP_FADD: case OP_FSUB: case OP_FMUL:
    case OP_FDIV: case OP_VECTOR_TIMES_SCALAR: case OP_DOT: case OP_SELECT: return 1;
    default: return 0;
    }
}

/* Bad ids and lengths fail the parse instead of reading past the words. */
static int parse(spv* m, const uint32_t* w, size_t n) {
    memset(m, 0, sizeof *m);
    if (n < 5 || w[0] != 0x07230203u || w[3] == 0 || w[3] > (1u << 22)) return 0;
    m->w = w, m->n = n, m->bound = w[3];
    m->def = calloc(m->bound, 4), m->name = calloc(m->bound, 4), m->func = calloc(m->bound, 4);
    m->nocon = calloc(m->bound, 1), m->seen = calloc(m->bound, 1);
    if (!m->def || !m->name || !m->func || !m->nocon || !m->seen) return 0;
    uint32_t cur = 0;
    for (size_t i = 5; i < n;) {
        uint32_t wc = w[i] >> 16, op = w[i] & 0xFFFFu;
        if (wc == 0 || i + wc > n) return 0;
        if (op == OP_NAME && wc >= 3 && w[i + 1] < m->bound) m->name[w[i + 1]] = (uint32_t)i + 2;
        else if (op == OP_DECORATE && wc >= 3 && w[i + 2] == DEC_NO_CONTRACTION && w[i + 1] < m->bound)
            m->nocon[w[i + 1]] = 1;
        else if (op == OP_FUNCTION && wc >= 3) cur = w[i + 2];
        else if (op == OP_FUNCTION_END) cur = 0;
        else if (wc >= 3 && has_result(op) && w[i + 2] < m->bound) {
            m->def[w[i + 2]] = (uint32_t)i;
            if (op == OP_VARIABLE) m->func[w[i + 2]] = cur;
        }
        i += wc;
    }
    return 1;
}

static void spv_free(spv* m) {
    free(m->def), free(m->name), free(m->func), free(m->nocon), free(m->seen);
}

/* Float operations in the expression of value id without NoContraction;
 * the first is described in what. */
static int bad_ops(spv* m, uint32_t id, char* what, size_t cap) {
    if (id >= m->bound || m->seen[id] || !m->def[id]) return 0;
    m->seen[id] = 1;
    uint32_t i = m->def[id], wc = m->w[i] >> 16, op = m->w[i] & 0xFFFFu;
    uint32_t from = 3, to = wc; /* operand words [from, to) that are ids */
    int bad = 0;
    switch (op) {
    case OP_FNEGATE: case OP_FADD: case OP_FSUB: case OP_FMUL: case OP_FDIV: case OP_VECTOR_TIMES_SCALAR:
    case OP_DOT:
        if (!m->nocon[id]) {
            if (!*what) snprintf(what, cap, "%%%u (opcode %u)", id, op);
            bad = 1;
        }
        break;
    case OP_COMPOSITE_CONSTRUCT: break;
    case OP_VECTOR_SHUFFLE: case OP_COMPOSITE_INSERT: to = 5; break;
    case OP_COMPOSITE_EXTRACT: to = 4; break;
    case OP_SELECT: from = 4; break;
    case OP_EXT_INST: from = 5; break; /* fma, clamp, ...: their arguments */
    default: return 0;                 /* loads, constants, parameters: another expression */
    }
    for (uint32_t k = from; k < to && k < wc; k++) bad += bad_ops(m, m->w[i + k], what, cap);
    return bad;
}

typedef struct count {
    int stores, bad;
} count;

/* Checks the stores into fn's listed variables; per-name store counts
 * (index as in vars) go to found. */
static count check_function(spv* m, const char* fn, const char* const* vars, int* found, const char* label) {
    count c = {0, 0};
    size_t fl = strlen(fn);
    uint32_t cur = 0;
    int in_fn = 0;
    for (size_t i = 5; i < m->n;) {
        uint32_t wc = m->w[i] >> 16, op = m->w[i] & 0xFFFFu;
        if (op == OP_FUNCTION) {
            cur = m->w[i + 2];
            char buf[128] = "";
            if (m->name[cur]) str_at(m, m->name[cur], buf, sizeof buf);
            in_fn = !strncmp(buf, fn, fl) && buf[fl] == '(';
        } else if (op == OP_FUNCTION_END) {
            in_fn = 0;
        } else if (in_fn && op == OP_STORE && wc >= 3) {
            uint32_t ptr = m->w[i + 1], val = m->w[i + 2];
            if (ptr < m->bound && m->def[ptr] && (m->w[m->def[ptr]] & 0xFFFFu) == OP_VARIABLE && m->func[ptr] == cur)
                for (int v = 0; vars[v]; v++)
                    if (name_is(m, ptr, vars[v])) {
                        char what[64] = "";
                        memset(m->seen, 0, m->bound);
                        int b = bad_ops(m, val, what, sizeof what);
                        c.stores++, found[v]++;
                        if (b) {
                            c.bad++;
                            fprintf(stderr, "  %s: %s: a store into %s has %d operation(s) without NoContraction, first %s\n",
                                    label, fn, vars[v], b, what);
                        }
                    }
        }
        i += wc;
    }
    return c;
}

/* Float arithmetic that a driver may contract or reassociate. Left out:
 * negation (exact) and OpDot, which glslang never decorates (a `precise`
 * dot stays undecorated; its products have no other use, so the driver
 * lowers it alike wherever it stands, while its operands and its users are
 * checked). */
static int is_float_arith(uint32_t op) {
    switch (op) {
    case OP_FADD: case OP_FSUB: case OP_FMUL: case OP_FDIV: case OP_FREM: case OP_FMOD: case OP_VECTOR_TIMES_SCALAR:
    case OP_MATRIX_TIMES_SCALAR: case OP_VECTOR_TIMES_MATRIX: case OP_MATRIX_TIMES_VECTOR: return 1;
    default: return 0;
    }
}

/* Every float operation in function fn (all of them, not only the stores'
 * expressions): the count in *ops, the ones without NoContraction returned
 * (the first few described); -1 where fn is not in the module. */
static int check_whole_function(const spv* m, const char* fn, int* ops, const char* label, int quiet) {
    size_t fl = strlen(fn);
    int in_fn = 0, found = 0, bad = 0;
    *ops = 0;
    for (size_t i = 5; i < m->n;) {
        uint32_t wc = m->w[i] >> 16, op = m->w[i] & 0xFFFFu;
        if (op == OP_FUNCTION) {
            uint32_t id = m->w[i + 2];
            char buf[128] = "";
            if (m->name[id]) str_at(m, m->name[id], buf, sizeof buf);
            in_fn = !strncmp(buf, fn, fl) && buf[fl] == '(';
            found |= in_fn;
        } else if (op == OP_FUNCTION_END) {
            in_fn = 0;
        } else if (in_fn && is_float_arith(op) && wc >= 3) {
            uint32_t id = m->w[i + 2];
            (*ops)++;
            if (id < m->bound && !m->nocon[id]) {
                if (bad < 3 && !quiet) fprintf(stderr, "  %s: %s: %%%u (opcode %u) without NoContraction\n", label, fn, id, op);
                bad++;
            }
        }
        i += wc;
    }
    return found ? bad : -1;
}

/* The path tracer's functions whose every float operation must be precise
 * (probes/shaders/probe.comp, path_common.glsl, render/shaders/sampling.glsl
 * and sky.glsl). */
static const char* const path_fns[] = {"render", "path", "surface", "bsdf_of", "bsdf_eval", "bsdf_sample_u", "basis",
                                       "cosine_dir", "cone_dir", "ggx_d", "ggx_lambda", "ggx_vndf", "fresnel_dielectric",
                                       "dielectric", "glass_walk", "nee", "area_hit", "emitter_point", "mis", "sky_eval",
                                       "direct", "trace_model", "trace_instance", "box_t", "safe_inv", NULL};

/* The bake's kernels' (probe.comp's bake() and bake_one(): probe and probe_one), whose every float operation
 * is precise too. */
static const char* const bake_fns[] = {"bake", "path", "surface", "bsdf_of", "bsdf_eval", "bsdf_sample_u", "basis",
                                       "cosine_dir", "cone_dir", "ggx_d", "ggx_lambda", "ggx_vndf", "fresnel_dielectric",
                                       "dielectric", "glass_walk", "nee", "area_hit", "emitter_point", "mis", "sky_eval",
                                       "trace_model", "trace_instance", "box_t", "safe_inv", NULL};
static const char* const bake_one_fns[] = {"bake_one", "surface", "bsdf_of", "bsdf_eval", "bsdf_sample_u", "basis",
                                           "cosine_dir", "sky_eval", "trace_model", "trace_instance", "box_t",
                                           "safe_inv", NULL};

/* The octree walk's functions (trace_common.glsl), whose every float operation WALK_PRECISE makes precise. */
static const char* const walk_fns[] = {"trace_model", "trace_instance", "box_t", "safe_inv", NULL};

/* The embedded kernels by the name of their array (vx__NAME_spv_arr), as VX_WALK_PRECISE_KERNELS names them. */
typedef struct kernel {
    const char* name;
    const uint32_t* w;
    size_t bytes;
} kernel;
#define KERNEL(n) {#n, vx__##n##_spv_arr, sizeof vx__##n##_spv_arr}
static const kernel kernels[] = {KERNEL(gbuffer), KERNEL(frame), KERNEL(frame_display), KERNEL(direct), KERNEL(ao),
                                 KERNEL(trace), KERNEL(trace_compact),
#ifdef VX_TEST_CONES
                                 KERNEL(cone_trace), KERNEL(cone_inject), KERNEL(cone_voxelize),
#endif
#ifdef VX_TEST_PHOTONS
                                 KERNEL(photon),
#endif
                                 {NULL, NULL, 0}};

/* Every float operation of the functions fns must carry NoContraction; the count of those that do not.
 * quiet: count only (a kernel expected to fail) */
static int check_fns(const char* label, const uint32_t* w, size_t bytes, const char* const* fns, const char* what,
                     int quiet) {
    spv m;
    int ok = parse(&m, w, bytes / 4), total_bad = 0, nf = 0;
    CHECKF(ok, "%s: not SPIR-V", label);
    if (ok)
        for (int f = 0; fns[f]; f++, nf++) {
            int ops = 0, bad = check_whole_function(&m, fns[f], &ops, label, quiet);
            /* the control (quiet: the bake's kernel) holds only its own entry's functions since each build of
             * probe.comp has one entry point (bake4): render() and what only it calls are not there */
            CHECKF(quiet || bad >= 0, "%s: no function %s", label, fns[f]);
            CHECKF(quiet || bad <= 0, "%s: %s: %d of %d float operations could be contracted", label, fns[f], bad, ops);
            CHECKF(bad < 0 || ops > 0, "%s: %s has no float operation (renamed?)", label, fns[f]);
            if (bad > 0) total_bad += bad;
        }
    printf("%-24s %s: %d functions, %d operations without NoContraction\n", label, what, nf, total_bad);
    spv_free(&m);
    return total_bad;
}

static int check_path_kernel(const char* label, const uint32_t* w, size_t bytes, int quiet) {
    return check_fns(label, w, bytes, path_fns, "path tracer", quiet);
}

/* Checks one kernel; need: the variables must be there (the float trace
 * kernels, whose DEEP 2 code holds them), else a kernel without them passes. */
static void check_kernel(const char* label, const uint32_t* w, size_t bytes, int need) {
    spv m;
    int ok = parse(&m, w, bytes / 4);
    CHECKF(ok, "%s: not SPIR-V", label);
    if (ok) {
        int fm[16] = {0}, fi[16] = {0};
        count a = check_function(&m, "trace_model", model_vars, fm, label);
        count b = check_function(&m, "trace_instance", inst_vars, fi, label);
        printf("%-24s trace_model: %d stores checked, %d bad; trace_instance: %d stores, %d bad\n", label, a.stores,
               a.bad, b.stores, b.bad);
        CHECKF(a.bad == 0 && b.bad == 0, "%s: %d error-free sums could be folded by the driver", label, a.bad + b.bad);
        if (need) {
            for (int v = 0; model_vars[v]; v++) CHECKF(fm[v] > 0, "%s: trace_model stores no %s", label, model_vars[v]);
            for (int v = 0; inst_vars[v]; v++) CHECKF(fi[v] > 0, "%s: trace_instance stores no %s", label, inst_vars[v]);
        }
    }
    spv_free(&m);
}

/* Each kernel of the list (names separated by spaces, as cmake/shaders.cmake's VX_WALK_PRECISE_KERNELS): its walk
 * and its secondary rays' start (gb_offset_point, where it has one) wholly precise; a name not in kernels[] fails
 * (the list grew past this test's table, or the kernel is not built here). */
static void check_listed(const char* list) {
    int listed = 0;
    for (const char* at = list; *at;) {
        size_t n = strcspn(at, " ,;");
        if (n) {
            char name[64];
            snprintf(name, sizeof name, "%.*s", (int)n, at);
            const kernel* k = kernels;
            while (k->name && strcmp(k->name, name)) k++;
            CHECKF(k->name != NULL, "listed kernel %s: not embedded in this test (kernels[]) or not built", name);
            if (k->name) {
                check_fns(name, k->w, k->bytes, walk_fns, "walk", 0);
                spv m;
                if (parse(&m, k->w, k->bytes / 4)) {
                    int ops = 0, bad = check_whole_function(&m, "gb_offset_point", &ops, name, 0);
                    if (bad >= 0) printf("%-24s gb_offset_point: %d of %d operations without NoContraction\n", name, bad, ops);
                    CHECKF(bad <= 0, "%s: gb_offset_point: %d of %d float operations could be contracted", name, bad, ops);
                }
                spv_free(&m);
            }
            listed++;
        }
        at += n;
        at += *at != 0;
    }
    CHECKF(listed > 0, "VX_WALK_PRECISE_KERNELS is empty");
}

static void test_embedded(void) {
    check_kernel("trace.comp", vx__trace_spv_arr, sizeof vx__trace_spv_arr, 1);
    check_kernel("trace_compact.comp", vx__trace_compact_spv_arr, sizeof vx__trace_compact_spv_arr, 1);
    /* the pass pipeline's kernels trace through trace_common.glsl too */
    check_kernel("frame.comp", vx__frame_spv_arr, sizeof vx__frame_spv_arr, 0);
    check_kernel("gbuffer.comp", vx__gbuffer_spv_arr, sizeof vx__gbuffer_spv_arr, 0);
    check_listed(VX_WALK_PRECISE_KERNELS);
    /* trace.comp's walk is not in the list (the control: the check sees what the define changes) */
    int ctl = check_fns("trace.comp", vx__trace_spv_arr, sizeof vx__trace_spv_arr, walk_fns, "walk", 1);
    CHECKF(ctl >= 50, "trace.comp's walk has only %d operations without NoContraction", ctl);
#ifdef VX_TEST_PROBES
    /* the render kernel's walk is trace_common.glsl's too */
    check_kernel("probe.comp (render)", vx__probe_pt_spv_arr, sizeof vx__probe_pt_spv_arr, 1);
    check_path_kernel("probe.comp (render)", vx__probe_pt_spv_arr, sizeof vx__probe_pt_spv_arr, 0);
    /* the bake's kernels too (bake(), bake_one() and what they call): with their path and walk contractible the
     * NVIDIA compiler gave eph_monu1's bake 88 bytes apart with and without the sun's depth map and the animated
     * demo's plain and compact bakes 150 hit distances one float step apart (issue 18, H200, branch rdr4) */
    check_fns("probe.comp (bake)", vx__probe_spv_arr, sizeof vx__probe_spv_arr, bake_fns, "path tracer", 0);
    check_fns("probe.comp (bake_one)", vx__probe_one_spv_arr, sizeof vx__probe_one_spv_arr, bake_one_fns,
              "path tracer", 0);
#ifdef VX_TEST_PHOTONS
    /* the photons' kernel shares path_common.glsl without PT_PREC (the control: the check sees what `precise`
     * changes in those functions) */
    int bad = check_path_kernel("photon.comp", vx__photon_spv_arr, sizeof vx__photon_spv_arr, 1);
    CHECKF(bad > 100, "the photons' kernel has only %d path operations without NoContraction", bad);
#endif
#endif
}

/* Truncated or garbage words are reported, never read past. */
static void test_bad_input(void) {
    spv m;
    uint32_t junk[8] = {0x07230203u, 0x10000, 0, 100, 0, 0xFFFF0005u, 1, 2};
    CHECK(!parse(&m, junk, 8));
    spv_free(&m);
    CHECK(!parse(&m, junk, 3));
    spv_free(&m);
    uint32_t cut[6] = {0x07230203u, 0x10000, 0, 100, 0, 0x00040047u}; /* OpDecorate of 4 words, 1 here */
    CHECK(!parse(&m, cut, 6));
    spv_free(&m);
}

/* argv: .spv files of the trace kernels, or after --path of the path
 * tracer's render kernel */
static int check_files(int argc, char** argv) {
    int path = argc > 1 && !strcmp(argv[1], "--path");
    for (int a = 1 + path; a < argc; a++) {
        FILE* f = fopen(argv[a], "rb");
        CHECKF(f != NULL, "%s: cannot open", argv[a]);
        if (!f) continue;
        uint32_t* buf = malloc(4u << 20);
        size_t n = buf ? fread(buf, 1, 4u << 20, f) : 0;
        fclose(f);
        if (buf && path) check_path_kernel(argv[a], buf, n, 0);
        else if (buf) check_kernel(argv[a], buf, n, 1);
        free(buf);
    }
    printf("%s\n", vx_t_failed_checks ? "FAILED" : "ok");
    return vx_t_failed_checks ? 1 : 0;
}

int main(int argc, char** argv) {
    if (argc > 1) return check_files(argc, argv);
    RUN(test_embedded);
    RUN(test_bad_input);
    return vx_test_finish();
}
