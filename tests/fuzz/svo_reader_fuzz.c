/* tests/fuzz/svo_reader_fuzz.c - libFuzzer target for the model reader
 * (vx_svo_reader_open, _next, _finish, _copy_graph, _model; svo/svo.h), which the
 * models path of the renderer takes (svo_render --load models) and which
 * svo_fuzz does not reach: the input goes into a memfd, so the reader maps
 * it as it maps a file on disk (its MADV_DONTNEED behind each model too).
 *
 * Each input is read twice by both paths, checksums on with one thread, then
 * off (so mutations reach the structure checks) with two threads taking
 * models at once (the lock, the CPUs' share). The reader is checked against
 * vx_svo_read of the same bytes (the independent path), a disagreement
 * aborts (a finding):
 * - the reader finishes exactly when the whole read succeeds (both refuse
 *   the same files), with the same models (digest, counts) and bounds;
 * - a model it hands over passes vx_svo_validate_model;
 * - after a refusal it hands over nothing more, and finish fails;
 * - the graph's copy has the whole read's instances. */
#define _GNU_SOURCE /* memfd_create */
#include <pthread.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <unistd.h>

#include "svo/svo.h"

typedef struct take_ctx {
    vx_svo_model_reader* rd;
    const vx_svo_scene* whole; /* NULL: the whole read refused the file */
    uint32_t taken, failed;
} take_ctx;

static void* take_models(void* arg) {
    take_ctx* t = arg;
    for (;;) {
        uint32_t i = 0;
        vx_svo_model m;
        vx_error err;
        if (vx_svo_reader_next(t->rd, &i, &m, &err) != VX_OK) {
            t->failed++;
            /* refused: nothing more, whoever asks */
            if (vx_svo_reader_next(t->rd, &i, &m, &err) == VX_OK) abort();
            return NULL;
        }
        const vx_svo_scene* g = vx_svo_reader_scene(t->rd);
        if (i >= g->model_count) return NULL; /* all taken */
        if (vx_svo_validate_model(&m, &err) != VX_OK) abort();
        if (t->whole) {
            const vx_svo_model* w = &t->whole->models[i];
            if (m.node_count != w->node_count || m.attr_count != w->attr_count || m.root != w->root ||
                m.voxel_count != w->voxel_count || vx_svo_model_digest(&m) != vx_svo_model_digest(w))
                abort();
        }
        vx_svo_model_free(NULL, &m);
        t->taken++;
    }
}

static void one_pass(const char* path, const uint8_t* data, size_t size, bool skip) {
    vx_error err;
    unsigned threads = skip ? 2u : 1u;
    vx_svo_read_desc d = {.skip_checksums = skip, .threads = threads};
    vx_svo_scene whole;
    bool whole_ok = vx_svo_read(&d, data, size, &whole, &err) == VX_OK;
    vx_svo_model_reader* rd = NULL;
    if (vx_svo_reader_open(&d, path, &rd, &err) != VX_OK) {
        /* the open checks the container and the graph: a file the whole read takes passes them */
        if (whole_ok) abort();
        return;
    }
    const vx_svo_scene* g = vx_svo_reader_scene(rd);
    vx_svo_model again;
    if (vx_svo_reader_model(rd, 0, &again, &err) == VX_OK) abort(); /* no random access before a finished pass */
    vx_svo_scene copy;
    if (vx_svo_reader_copy_graph(rd, NULL, &copy, &err) == VX_OK) {
        if (copy.model_count != g->model_count || copy.instance_count != g->instance_count) abort();
        for (uint32_t i = 0; i < copy.model_count; i++)
            if (copy.models[i].nodes || copy.models[i].palette) abort(); /* a graph: no trees */
        if (whole_ok && (copy.instance_count != whole.instance_count || copy.model_count != whole.model_count)) abort();
        for (uint32_t i = 0; whole_ok && i < copy.instance_count; i++) {
            const vx_svo_instance *a = &copy.instances[i], *b = &whole.instances[i];
            if (a->model != b->model || a->layer != b->layer || a->flags != b->flags ||
                memcmp(a->xform, b->xform, sizeof a->xform) || strcmp(a->name, b->name))
                abort();
        }
        vx_svo_scene_free(&copy);
    }
    take_ctx t[2] = {{.rd = rd, .whole = whole_ok ? &whole : NULL}, {.rd = rd, .whole = whole_ok ? &whole : NULL}};
    pthread_t th;
    bool two = threads > 1 && pthread_create(&th, NULL, take_models, &t[1]) == 0;
    take_models(&t[0]);
    if (two) pthread_join(th, NULL);
    uint32_t taken = t[0].taken + t[1].taken, failed = t[0].failed + t[1].failed;
    bool finished = vx_svo_reader_finish(rd, &err) == VX_OK;
    if (finished && (failed || taken != g->model_count)) abort(); /* finish after a refusal or a model short */
    if (finished != whole_ok) abort();                            /* both paths take the same files */
    if (finished && (memcmp(g->bounds_min, whole.bounds_min, sizeof g->bounds_min) ||
                     memcmp(g->bounds_max, whole.bounds_max, sizeof g->bounds_max)))
        abort();
    /* after a finished pass every model is read again at random, the same model as the pass's (and the whole
     * read's); an index past the models is refused */
    for (uint32_t i = 0; finished && i <= g->model_count; i++) {
        bool ok = vx_svo_reader_model(rd, i, &again, &err) == VX_OK;
        if (ok != (i < g->model_count)) abort();
        if (!ok) continue;
        if (vx_svo_model_digest(&again) != vx_svo_model_digest(&whole.models[i]) ||
            again.node_count != whole.models[i].node_count || again.attr_count != whole.models[i].attr_count)
            abort();
        vx_svo_model_free(NULL, &again);
    }
    vx_svo_reader_close(rd);
    if (whole_ok) vx_svo_scene_free(&whole);
}

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    int fd = memfd_create("svo_reader_fuzz", MFD_CLOEXEC);
    if (fd < 0) return 0;
    size_t at = 0;
    while (at < size) {
        ssize_t n = write(fd, data + at, size - at);
        if (n <= 0) break;
        at += (size_t)n;
    }
    char path[64];
    snprintf(path, sizeof path, "/proc/self/fd/%d", fd);
    if (at == size)
        for (int skip = 0; skip < 2; skip++) one_pass(path, data, size, skip != 0);
    close(fd);
    return 0;
}
