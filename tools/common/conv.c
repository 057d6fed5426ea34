/* tools/common/conv.c */
#define _POSIX_C_SOURCE 200809L
#include "tools/common/conv.h"

#include <ctype.h>
#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "convert/file.h"
#ifdef VX_HAVE_VDB
#include "convert/volume.h"
#endif
#include "tools/common/tool.h"

vx_tool_conv vx_tool_conv_defaults(void) {
    vx_tool_conv c = {0};
    c.res = vx_conv_file_defaults().res; /* one source of the converters' defaults */
    return c;
}

bool vx_tool_conv_option(int argc, char** argv, int* i, vx_tool_conv* c, void (*usage)(int)) {
    const char* a = argv[*i];
    if (!strcmp(a, "--frame")) {
        if (!vx_tool_parse_u32(vx_tool_arg(argc, argv, i, usage), &c->frame))
            vx_tool_usage_error(usage, "bad --frame value '%s'", argv[*i]);
        c->frame_set = true;
    } else if (!strcmp(a, "--keep-hidden")) c->keep_hidden = true;
    else if (!strcmp(a, "--keep-unused")) c->keep_unused = true;
    else if (!strcmp(a, "--no-collapse")) c->no_collapse = true;
    else if (!strcmp(a, "--no-dag")) c->no_dag = true;
    else if (!strcmp(a, "--res")) {
        if (!vx_tool_parse_u32(vx_tool_arg(argc, argv, i, usage), &c->res) || c->res < 1 ||
            c->res > VX_CONV_MESH_RES_MAX)
            vx_tool_usage_error(usage, "bad --res value '%s' (1 to %u)", argv[*i], VX_CONV_MESH_RES_MAX);
    } else if (!strcmp(a, "--region")) {
        uint32_t v = 0;
        if (!vx_tool_parse_u32(vx_tool_arg(argc, argv, i, usage), &v) || v < 64 || v > 65536 || (v & (v - 1)))
            vx_tool_usage_error(usage, "bad --region value '%s' (a power of two from 64 to 65536)", argv[*i]);
        c->region = v;
    } else if (!strcmp(a, "--scene")) {
        if (!vx_tool_parse_u32(vx_tool_arg(argc, argv, i, usage), &c->scene))
            vx_tool_usage_error(usage, "bad --scene value '%s'", argv[*i]);
        c->scene_set = true;
    } else if (!strcmp(a, "--solid")) c->solid = true;
    else if (!strcmp(a, "--normals")) c->normals = true;
    else if (!strcmp(a, "--y-up")) c->y_up = true;
    else if (!strcmp(a, "--grid")) c->grid = vx_tool_arg(argc, argv, i, usage);
    else if (!strcmp(a, "--threshold")) {
        if (!vx_tool_parse_double(vx_tool_arg(argc, argv, i, usage), &c->threshold))
            vx_tool_usage_error(usage, "bad --threshold value '%s'", argv[*i]);
        c->threshold_set = true;
    } else if (!strcmp(a, "--density")) c->density = true;
    else if (!strcmp(a, "--color")) c->color = vx_tool_arg(argc, argv, i, usage);
    else if (!strcmp(a, "--max-memory")) {
        if (!vx_tool_parse_bytes(vx_tool_arg(argc, argv, i, usage), &c->max_memory) || !c->max_memory)
            vx_tool_usage_error(usage, "bad --max-memory value '%s' (bytes, e.g. 512M or 4G)", argv[*i]);
    }
    else return false;
    return true;
}

static uint64_t file_size(const char* path) {
    FILE* f = fopen(path, "rb");
    if (!f) return 0;
    long n = fseek(f, 0, SEEK_END) == 0 ? ftell(f) : -1;
    fclose(f);
    return n > 0 ? (uint64_t)n : 0;
}

/* ---- frame sequences ----------------------------------------------------------- */
#ifdef VX_HAVE_VDB

typedef struct seq_file {
    unsigned long long number;
    char* path;
} seq_file;

static int cmp_seq(const void* a, const void* b) {
    const seq_file *p = (const seq_file*)a, *q = (const seq_file*)b;
    return p->number < q->number ? -1 : p->number > q->number;
}

static void free_paths(char** paths, uint32_t n) {
    for (uint32_t i = 0; paths && i < n; i++) free(paths[i]);
    free(paths);
}

static bool push_path(seq_file** v, size_t* n, size_t* cap, unsigned long long number, const char* dir, const char* name) {
    if (*n == *cap) {
        size_t c = *cap ? *cap * 2 : 64;
        seq_file* w = realloc(*v, c * sizeof *w);
        if (!w) return false;
        *v = w, *cap = c;
    }
    size_t len = strlen(dir) + strlen(name) + 2;
    char* p = malloc(len);
    if (!p) return false;
    snprintf(p, len, "%s%s%s", dir, dir[0] ? "/" : "", name);
    (*v)[(*n)++] = (seq_file){number, p};
    return true;
}

/* The files of a numbered sequence: a run of # (smoke_####.vdb: exactly
 * that many digits) or a printf number (smoke_%04d.vdb: at least 4, %d:
 * any) in the file name; the existing files that match, by number. */
static vx_result pattern_paths(const char* pattern, char*** out, uint32_t* count, vx_error* err) {
    const char* slash = strrchr(pattern, '/');
    const char* name = slash ? slash + 1 : pattern;
    char dir[4096];
    snprintf(dir, sizeof dir, "%.*s", slash ? (int)(slash - pattern) : 0, pattern);
    const char* hash = strchr(name, '#');
    const char* pct = strchr(name, '%');
    size_t pre = 0, width = 0, post = 0; /* prefix length, digits, where the suffix starts */
    bool exact = false;
    if (hash && (!pct || hash < pct)) {
        pre = (size_t)(hash - name);
        while (name[pre + width] == '#') width++;
        post = pre + width, exact = true;
    } else if (pct) {
        pre = (size_t)(pct - name);
        const char* q = pct + 1;
        bool zero = *q == '0';
        char* e;
        unsigned long w = strtoul(q, &e, 10);
        if (*e != 'd' && *e != 'u') return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "%s: only %%d, %%u and %%0Nd number a sequence", pattern);
        width = zero ? (size_t)w : 0;
        post = (size_t)(e + 1 - name);
    }
    const char* suffix = name + post;
    if (strchr(suffix, '#') || strchr(suffix, '%') || memchr(name, '/', pre))
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "%s: one number pattern in the file name only", pattern);
    DIR* dp = opendir(dir[0] ? dir : ".");
    if (!dp) return vx_fail(err, VX_ERR_IO, VX_NO_OFFSET, "%s: cannot list the folder '%s'", pattern, dir[0] ? dir : ".");
    seq_file* v = NULL;
    size_t n = 0, cap = 0, sl = strlen(suffix);
    bool ok = true;
    for (struct dirent* de; ok && (de = readdir(dp));) {
        const char* e = de->d_name;
        size_t len = strlen(e);
        if (len < pre + sl + 1 || strncmp(e, name, pre) || strcmp(e + len - sl, suffix)) continue;
        size_t digits = len - pre - sl;
        if ((exact && digits != width) || digits < width || digits > 18) continue;
        bool all = true;
        for (size_t k = 0; k < digits; k++) all = all && isdigit((unsigned char)e[pre + k]);
        if (all) ok = push_path(&v, &n, &cap, strtoull(e + pre, NULL, 10), dir, e);
    }
    closedir(dp);
    if (ok && n == 0) {
        free(v);
        return vx_fail(err, VX_ERR_IO, VX_NO_OFFSET, "%s: no file matches", pattern);
    }
    if (!ok || n > UINT32_MAX) {
        for (size_t i = 0; i < n; i++) free(v[i].path);
        free(v);
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "%s: out of memory", pattern);
    }
    qsort(v, n, sizeof *v, cmp_seq);
    char** paths = malloc(n * sizeof *paths);
    for (size_t i = 0; i < n; i++) {
        if (paths) paths[i] = v[i].path;
        else free(v[i].path);
    }
    free(v);
    if (!paths) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "%s: out of memory", pattern);
    *out = paths;
    *count = (uint32_t)n;
    return VX_OK;
}

/* A list file: one path per line (blank lines and lines starting with #
 * skipped), relative paths from the list's folder. */
static vx_result list_paths(const char* list, char*** out, uint32_t* count, vx_error* err) {
    uint8_t* data = NULL;
    size_t size = 0;
    vx_result r = vx_file_read(list, NULL, (uint64_t)1 << 26, &data, &size, err);
    if (r != VX_OK) return vx_error_prefix(err, list), r;
    const char* slash = strrchr(list, '/');
    char dir[4096];
    snprintf(dir, sizeof dir, "%.*s", slash ? (int)(slash - list) : 0, list);
    seq_file* v = NULL;
    size_t n = 0, cap = 0;
    bool ok = true;
    for (size_t i = 0; ok && i < size;) {
        size_t e = i;
        while (e < size && data[e] != '\n') e++;
        size_t end = e;
        while (end > i && (data[end - 1] == '\r' || data[end - 1] == ' ' || data[end - 1] == '\t')) end--;
        if (end > i && data[i] != '#') {
            char line[4096];
            snprintf(line, sizeof line, "%.*s", (int)(end - i), (const char*)data + i);
            ok = push_path(&v, &n, &cap, n, line[0] == '/' ? "" : dir, line);
        }
        i = e + 1;
    }
    vx_free(NULL, data);
    char** paths = ok && n ? malloc(n * sizeof *paths) : NULL;
    for (size_t i = 0; i < n; i++) {
        if (paths) paths[i] = v[i].path;
        else free(v[i].path);
    }
    free(v);
    if (!paths) return vx_fail(err, ok ? VX_ERR_BAD_FORMAT : VX_ERR_NOMEM, VX_NO_OFFSET, "%s: %s", list, ok ? "lists no files" : "out of memory");
    *out = paths;
    *count = (uint32_t)n;
    return VX_OK;
}


/* A .vdb sequence (vx_tool_conv_is_sequence) with the options of d. */
static vx_result load_sequence(const char* path, const vx_conv_file_desc* d, vx_tool_loaded* li, vx_svo_scene* out,
                               vx_error* err) {
    char** paths = NULL;
    uint32_t n = 0;
    vx_result r = !strcmp(vx_tool_ext(path), "txt") ? list_paths(path, &paths, &n, err) : pattern_paths(path, &paths, &n, err);
    if (r == VX_OK) {
        li->in_bytes = 0;
        for (uint32_t i = 0; i < n; i++) li->in_bytes += file_size(paths[i]);
        vx_conv_vdb_desc vd = {.build = d->build, .alloc = d->alloc, .logger = d->logger, .grid = d->grid, .solid = d->solid,
                               .threshold_set = d->threshold_set, .threshold = d->threshold, .density = d->density,
                               .color_grid = d->color_grid};
        r = vx_conv_vdb_sequence(&vd, (const char* const*)paths, n, out, &li->stats, err);
        li->seconds_read = li->stats.seconds_read;
    }
    free_paths(paths, n);
    return r;
}
#else
static vx_result load_sequence(const char* path, const vx_conv_file_desc* d, vx_tool_loaded* li, vx_svo_scene* out,
                               vx_error* err) {
    (void)path, (void)d, (void)li, (void)out;
    return vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET, "this build has no OpenVDB support");
}
#endif

bool vx_tool_conv_is_sequence(const char* path) {
    const char* ext = vx_tool_ext(path);
    return !strcmp(ext, "txt") || (!strcmp(ext, "vdb") && (strchr(path, '#') || strchr(path, '%')));
}

vx_conv_file_desc vx_tool_conv_file_desc(const vx_tool_conv* c, bool allow_svo, const vx_logger* log,
                                         vx_progress progress) {
    return (vx_conv_file_desc){
        .build = {.no_collapse = c->no_collapse, .no_dag = c->no_dag, .progress = progress},
        .alloc = c->alloc,
        .logger = log,
        .allow_svo = allow_svo,
        .frame = c->frame,
        .one_frame = c->frame_set,
        .keep_hidden = c->keep_hidden,
        .keep_unused = c->keep_unused,
        .res = c->res,
        .region = c->region,
        .scene_set = c->scene_set,
        .scene = c->scene,
        .normals = c->normals,
        .y_up = c->y_up,
        .solid = c->solid,
        .grid = c->grid,
        .threshold_set = c->threshold_set,
        .threshold = c->threshold,
        .density = c->density,
        .color_grid = c->color,
        .mesh_backend = c->mesh_backend,
    };
}

vx_result vx_tool_conv_load(const char* path, const vx_tool_conv* c, bool allow_svo, const vx_logger* log,
                            vx_progress progress, vx_svo_scene* out, vx_tool_loaded* info, vx_error* err) {
    vx_tool_loaded li = {0};
    vx_conv_file_desc d = vx_tool_conv_file_desc(c, allow_svo, log, progress);
    double t0 = vx_time_now();
    li.in_bytes = file_size(path);
    vx_result r;
    if (vx_tool_conv_is_sequence(path)) {
        li.kind = ".vdb sequence";
        r = load_sequence(path, &d, &li, out, err);
    } else {
        li.kind = vx_conv_file_kind(path);
        r = vx_conv_file(&d, path, out, &li.stats, err);
        li.seconds_read = li.stats.seconds_read;
    }
    li.seconds_total = vx_time_now() - t0;
    if (r == VX_OK && info) *info = li;
    return r;
}
