/* python/voxkit.c - the Python module `voxkit`: a C extension over the
 * public C API of the installed libvoxkit (only <voxkit/...> headers), with
 * numpy arrays out.
 *
 *   import voxkit
 *   s = voxkit.open("castle.vox")          # .svo as it is; .vox, .gltf/.glb, .vdb converted
 *   s.models, s.instances                  # lists of dicts (sizes, 3x4 transforms, names)
 *   xyz, rgba = s.voxels(0)                # model cells (N,3) int32, colours (N,4) uint8
 *   xyz, rgba = s.scene_voxels()           # grid cells, instances applied (= svo_info --dump)
 *   s.frame_count, s.frame_rate            # an animation: s.frame_instances(n), s.scene_voxels(frame=n)
 *   s.sky = "gradient:0.2,0.3,0.6:0.7,0.7,0.8:0.1,0.1,0.1"   # the stored sky, svo_render --sky's text (None: default)
 *   img = s.render(320, 240)               # (H,W,4) float32, lavapipe or a GPU (cpu=True: reference)
 *   s.save("castle.svo"); voxkit.convert("duck.glb", "duck.svo", res=128)
 *   s.to_vox("castle.vox"); s.to_glb("castle.glb"); s.to_vdb("castle.vdb")
 *
 * Errors raise voxkit.Error (a subclass of Exception) whose message is
 * voxkit's, prefixed with the file it concerns; its attributes path, code
 * (vx_result_str) and offset (byte offset or None) say the same by part.
 * Long calls (conversion, decoding, rendering) release the GIL.
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#define NPY_NO_DEPRECATED_API NPY_1_7_API_VERSION
#include <numpy/arrayobject.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "voxkit/convert/convert.h"
#include "voxkit/convert/export.h"
#include "voxkit/convert/file.h"
#include "voxkit/svo/svo.h"
#include "voxkit/version.h"
#ifdef VX_PY_RENDER
#include "voxkit/render/render.h"
#endif

static PyObject* vx_py_error; /* voxkit.Error */
static PyObject* vx_py_quantize_warning; /* voxkit.QuantizeWarning */

/* Raises voxkit.Error for err, naming path (may be NULL) as the tools do. */
static PyObject* raise_error(const char* path, const vx_error* err) {
    char msg[512];
    const char* m = err->msg[0] ? err->msg : vx_result_str(err->code);
    const char* named = path && !strstr(m, path) ? path : NULL; /* file errors name it already */
    int n = snprintf(msg, sizeof msg, "%s%s%s", named ? named : "", named ? ": " : "", m);
    if (err->offset != VX_NO_OFFSET && !strstr(m, "byte") && n > 0 && (size_t)n < sizeof msg)
        snprintf(msg + n, sizeof msg - (size_t)n, " (at byte %llu)", (unsigned long long)err->offset);
    PyObject* e = PyObject_CallFunction(vx_py_error, "s", msg);
    if (!e) return NULL;
    PyObject* off = err->offset == VX_NO_OFFSET ? Py_NewRef(Py_None) : PyLong_FromUnsignedLongLong(err->offset);
    PyObject* p = path ? PyUnicode_DecodeFSDefault(path) : Py_NewRef(Py_None);
    PyObject* code = PyUnicode_FromString(vx_result_str(err->code));
    if (off && p && code && !PyObject_SetAttrString(e, "path", p) && !PyObject_SetAttrString(e, "code", code) &&
        !PyObject_SetAttrString(e, "offset", off))
        PyErr_SetObject(vx_py_error, e);
    Py_XDECREF(off);
    Py_XDECREF(p);
    Py_XDECREF(code);
    Py_DECREF(e);
    return NULL;
}

/* ---- Scene -------------------------------------------------------------------------- */

typedef struct {
    PyObject_HEAD
    vx_svo_scene s;
    bool loaded;
    char* path; /* the file it was opened from (malloc; NULL if unknown): where a map sky's relative path starts */
#ifdef VX_PY_RENDER
    vx_gpu* gpu;
    vx_render_scene* rs;
    char* device; /* what gpu was created for (malloc) */
    PyThread_type_lock lock; /* one GPU frame at a time (render releases the GIL) */
#endif
} Scene;

static void scene_dealloc(Scene* self) {
#ifdef VX_PY_RENDER
    if (self->rs) vx_render_scene_destroy(self->rs);
    if (self->gpu) vx_gpu_destroy(self->gpu);
    free(self->device);
    if (self->lock) PyThread_free_lock(self->lock);
#endif
    if (self->loaded) vx_svo_scene_free(&self->s);
    free(self->path);
    Py_TYPE(self)->tp_free((PyObject*)self);
}

static PyTypeObject SceneType;

/* A (rows, cols) float64 array copied from a row-major matrix. */
static PyObject* matrix(const double* m, npy_intp rows, npy_intp cols) {
    npy_intp dims[2] = {rows, cols};
    PyObject* a = PyArray_SimpleNew(2, dims, NPY_FLOAT64);
    if (a) memcpy(PyArray_DATA((PyArrayObject*)a), m, sizeof(double) * (size_t)(rows * cols));
    return a;
}

static PyObject* attr_names(uint32_t attrs) {
    static const char* names[] = {"palette", "rgba8", "normal", "material", "density"};
    PyObject* l = PyList_New(0);
    for (int i = 0; l && i < 5; i++)
        if (attrs & (1u << i)) {
            PyObject* n = PyUnicode_FromString(names[i]);
            if (!n || PyList_Append(l, n)) {
                Py_XDECREF(n);
                Py_DECREF(l);
                return NULL;
            }
            Py_DECREF(n);
        }
    return l;
}

static PyObject* scene_models(Scene* self, void* closure) {
    (void)closure;
    PyObject* l = PyList_New(self->s.model_count);
    for (uint32_t i = 0; l && i < self->s.model_count; i++) {
        const vx_svo_model* m = &self->s.models[i];
        PyObject* d = Py_BuildValue("{s:(III),s:I,s:K,s:N}", "size", m->size[0], m->size[1], m->size[2], "depth",
                                    m->depth, "voxel_count", (unsigned long long)m->voxel_count, "attrs",
                                    attr_names(m->attrs));
        if (!d) {
            Py_DECREF(l);
            return NULL;
        }
        PyList_SET_ITEM(l, i, d);
    }
    return l;
}

/* The instances of s (the scene or a view of one frame) as dicts. */
static PyObject* instance_list(const vx_svo_scene* s) {
    PyObject* l = PyList_New(s->instance_count);
    for (uint32_t i = 0; l && i < s->instance_count; i++) {
        const vx_svo_instance* in = &s->instances[i];
        double w[12];
        vx_svo_instance_world(s, in, w);
        PyObject* layer = in->layer < s->layer_count ? PyUnicode_FromString(s->layers[in->layer].name)
                                                     : Py_NewRef(Py_None);
        PyObject* d = Py_BuildValue("{s:I,s:s,s:N,s:N,s:N,s:O,s:O}", "model", in->model, "name", in->name, "layer",
                                    layer, "xform", matrix(in->xform, 3, 4), "world", matrix(w, 3, 4), "hidden",
                                    (in->flags & VX_SVO_INSTANCE_HIDDEN) ? Py_True : Py_False, "visible",
                                    vx_svo_instance_visible(s, i) ? Py_True : Py_False);
        if (!d) {
            Py_DECREF(l);
            return NULL;
        }
        PyList_SET_ITEM(l, i, d);
    }
    return l;
}

static PyObject* scene_instances(Scene* self, void* closure) {
    (void)closure;
    return instance_list(&self->s);
}

static PyObject* scene_frame_count(Scene* self, void* closure) {
    (void)closure;
    return PyLong_FromUnsignedLong(vx_svo_scene_frames(&self->s));
}

static PyObject* scene_frame_rate(Scene* self, void* closure) {
    (void)closure;
    return PyFloat_FromDouble(self->s.frame_rate);
}

/* Frame f of the scene as a view (borrowing self's arrays); IndexError
 * when out of range. */
static bool frame_view(Scene* self, unsigned int f, vx_svo_scene* view) {
    if (vx_svo_scene_frame(&self->s, f, view)) return true;
    PyErr_Format(PyExc_IndexError, "frame %u out of range (the scene has %u)", f, vx_svo_scene_frames(&self->s));
    return false;
}

static PyObject* scene_frame_instances(Scene* self, PyObject* args) {
    unsigned int f;
    vx_svo_scene view;
    if (!PyArg_ParseTuple(args, "I:frame_instances", &f) || !frame_view(self, f, &view)) return NULL;
    return instance_list(&view);
}

static PyObject* scene_world_from_grid(Scene* self, void* closure) {
    (void)closure;
    return matrix(self->s.world_from_grid, 3, 4);
}

static PyObject* scene_bounds(Scene* self, void* closure) {
    (void)closure;
    double lo[3], hi[3];
    vx_svo_scene_world_bounds(&self->s, lo, hi);
    return Py_BuildValue("((ddd)(ddd))", lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]);
}

/* Decoding into arrays: cells of one model, or the scene's grid cells. */
typedef struct decode_ctx {
    const vx_svo_scene* s;
    const vx_svo_model* m;
    const double* xform; /* NULL: model cells */
    int32_t* xyz32;
    int64_t* xyz64;
    uint8_t* rgba;
    size_t n, cap;
    bool overflow; /* more cells than the model's voxel_count */
} decode_ctx;

static bool decode_cell(void* user, uint32_t x, uint32_t y, uint32_t z, uint32_t attr) {
    decode_ctx* c = (decode_ctx*)user;
    if (c->n >= c->cap) {
        c->overflow = true;
        return false;
    }
    if (c->xform) { /* the grid cell: floor(M (v + 1/2) + t), as svo_info --dump */
        const double* M = c->xform;
        double p[3] = {x + 0.5, y + 0.5, z + 0.5};
        for (int r = 0; r < 3; r++)
            c->xyz64[3 * c->n + (size_t)r] =
                (int64_t)floor(M[r * 4] * p[0] + M[r * 4 + 1] * p[1] + M[r * 4 + 2] * p[2] + M[r * 4 + 3]);
    } else {
        c->xyz32[3 * c->n] = (int32_t)x, c->xyz32[3 * c->n + 1] = (int32_t)y, c->xyz32[3 * c->n + 2] = (int32_t)z;
    }
    uint32_t col = vx_svo_attr_color(c->s, c->m, attr);
    for (int k = 0; k < 4; k++) c->rgba[4 * c->n + (size_t)k] = (uint8_t)(col >> (8 * k));
    c->n++;
    return true;
}

/* Decodes models[i] placed by xforms[i] (grid cells, int64), or with
 * xforms NULL in model cells (int32), into new arrays: (xyz, rgba). */
static PyObject* decode_arrays(Scene* self, const uint32_t* models, const double* const* xforms, size_t count,
                               bool grid) {
    uint64_t total = 0;
    for (size_t i = 0; i < count; i++) total += self->s.models[models[i]].voxel_count;
    if (total > (uint64_t)NPY_MAX_INTP / 8)
        return PyErr_Format(PyExc_MemoryError, "%llu voxels do not fit an array", (unsigned long long)total);
    npy_intp d3[2] = {(npy_intp)total, 3}, d4[2] = {(npy_intp)total, 4};
    PyArrayObject* xyz = (PyArrayObject*)PyArray_SimpleNew(2, d3, grid ? NPY_INT64 : NPY_INT32);
    PyArrayObject* rgba = (PyArrayObject*)PyArray_SimpleNew(2, d4, NPY_UINT8);
    if (!xyz || !rgba) {
        Py_XDECREF(xyz);
        Py_XDECREF(rgba);
        return NULL;
    }
    decode_ctx c = {.s = &self->s, .cap = (size_t)total};
    if (grid) c.xyz64 = (int64_t*)PyArray_DATA(xyz);
    else c.xyz32 = (int32_t*)PyArray_DATA(xyz);
    c.rgba = (uint8_t*)PyArray_DATA(rgba);
    vx_error err = {0};
    vx_result r = VX_OK;
    Py_BEGIN_ALLOW_THREADS
    for (size_t i = 0; i < count && r == VX_OK; i++) {
        c.m = &self->s.models[models[i]];
        c.xform = xforms ? xforms[i] : NULL;
        size_t before = c.n;
        r = vx_svo_decode_model(c.m, decode_cell, &c, &err);
        if (r == VX_OK && (c.overflow || c.n - before != c.m->voxel_count))
            r = vx_fail(&err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "model %u decodes to %s cells than its voxel count %llu",
                        models[i], c.overflow ? "more" : "fewer", (unsigned long long)c.m->voxel_count);
    }
    Py_END_ALLOW_THREADS
    if (r != VX_OK) {
        Py_DECREF(xyz);
        Py_DECREF(rgba);
        return raise_error(NULL, &err);
    }
    return Py_BuildValue("(NN)", (PyObject*)xyz, (PyObject*)rgba);
}

static PyObject* scene_voxels(Scene* self, PyObject* args) {
    unsigned int model;
    if (!PyArg_ParseTuple(args, "I:voxels", &model)) return NULL;
    if (model >= self->s.model_count)
        return PyErr_Format(PyExc_IndexError, "model %u out of range (the scene has %u)", model, self->s.model_count);
    uint32_t m = model;
    return decode_arrays(self, &m, NULL, 1, false);
}

static PyObject* scene_scene_voxels(Scene* self, PyObject* args, PyObject* kw) {
    static char* kwlist[] = {"all", "frame", NULL};
    int all = 0;
    unsigned int frame = 0;
    vx_svo_scene view;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "|pI:scene_voxels", kwlist, &all, &frame) ||
        !frame_view(self, frame, &view))
        return NULL;
    const vx_svo_scene* s = &view;
    uint32_t* models = PyMem_Calloc(s->instance_count + 1, sizeof(uint32_t));
    const double** xf = PyMem_Calloc(s->instance_count + 1, sizeof(double*));
    if (!models || !xf) {
        PyMem_Free(models);
        PyMem_Free(xf);
        return PyErr_NoMemory();
    }
    size_t n = 0;
    for (uint32_t i = 0; i < s->instance_count; i++)
        if (s->instances[i].model < s->model_count && (all || vx_svo_instance_visible(s, i))) {
            models[n] = s->instances[i].model;
            xf[n++] = s->instances[i].xform;
        }
    PyObject* r = decode_arrays(self, models, xf, n, true);
    PyMem_Free(models);
    PyMem_Free(xf);
    return r;
}

/* Scene.sky: the sky as svo_render's --sky text (svo.h vx_sky_parse /
 * vx_sky_format), None for the default. A map's path is stored from the
 * scene file's folder (as vox2svo --sky stores it) but read and given from
 * the current folder, as the option takes it: `s.sky = s.sky` keeps the
 * record, and the text read works as svo_render --sky from here. */
static PyObject* scene_get_sky(Scene* self, void* closure) {
    (void)closure;
    if (self->s.sky.type == VX_SKY_DEFAULT) return Py_NewRef(Py_None);
    vx_sky k = self->s.sky;
    vx_error err = {0};
    if (vx_sky_rebase(&k, self->path, NULL, &err) != VX_OK) {
        /* the file's folder no longer resolves (or the path grew too long):
         * the path joined to it as text still names the image from here */
        char joined[VX_SKY_PATH_MAX + 1];
        if (!vx_sky_path(&self->s.sky, self->path, joined, sizeof joined)) return raise_error(self->path, &err);
        memcpy(k.path, joined, sizeof k.path);
    }
    char t[VX_SKY_SPEC_MAX];
    if (vx_sky_format(&k, t, sizeof t, &err) != VX_OK) return raise_error(self->path, &err);
    return PyUnicode_FromString(t);
}

static int scene_set_sky(Scene* self, PyObject* v, void* closure) {
    (void)closure;
    vx_sky k = {0}; /* None and del: the default (nothing stored) */
    if (v && v != Py_None) {
        if (!PyUnicode_Check(v)) {
            PyErr_Format(PyExc_TypeError, "Scene.sky takes a str (svo_render --sky's syntax) or None, not %.80s",
                         Py_TYPE(v)->tp_name);
            return -1;
        }
        Py_ssize_t len;
        const char* spec = PyUnicode_AsUTF8AndSize(v, &len);
        if (!spec) return -1;
        vx_error err = {0};
        if ((size_t)len != strlen(spec)) {
            PyErr_SetString(PyExc_ValueError, "bad sky: the text holds a NUL character");
            return -1;
        }
        if (vx_sky_parse(spec, &k, &err) != VX_OK) {
            PyErr_Format(PyExc_ValueError, "bad sky '%.300s': %s", spec, err.msg);
            return -1;
        }
        /* given from the current folder, stored from the scene file's */
        if (vx_sky_rebase(&k, NULL, self->path, &err) != VX_OK) {
            raise_error(self->path, &err);
            return -1;
        }
    }
    self->s.sky = k;
    return 0;
}

/* Writes scene s, read from from_path (NULL: unknown, the current folder),
 * to path: a map sky's relative path (relative to the file's folder) is
 * rebased for path's folder on a copy, so the saved file names the same
 * image (vx_sky_rebase; s itself is unchanged). */
static vx_result write_svo(const vx_svo_scene* s, const char* from_path, const char* path, vx_error* err) {
    vx_svo_scene w = *s; /* shallow: the write only reads it */
    vx_result r = vx_sky_rebase(&w.sky, from_path, path, err);
    return r ? r : vx_svo_write_file(NULL, &w, path, err);
}

static PyObject* scene_save(Scene* self, PyObject* args) {
    PyObject* pathobj;
    if (!PyArg_ParseTuple(args, "O&:save", PyUnicode_FSConverter, &pathobj)) return NULL;
    const char* path = PyBytes_AS_STRING(pathobj);
    vx_error err = {0};
    vx_result r;
    Py_BEGIN_ALLOW_THREADS
    r = write_svo(&self->s, self->path, path, &err);
    Py_END_ALLOW_THREADS
    PyObject* out = r == VX_OK ? Py_NewRef(Py_None) : raise_error(path, &err);
    Py_DECREF(pathobj);
    return out;
}

/* A lossy export warns (voxkit.QuantizeWarning, a UserWarning, through the
 * warnings module: shown once by default, filtered, recorded or raised as
 * the caller's filters say) rather than returning what it lost: to_vox's
 * result stays None, as save's. */
static PyObject* scene_to_vox(Scene* self, PyObject* args, PyObject* kw) {
    static char* kwlist[] = {"path", "quantize", NULL};
    PyObject* pathobj;
    int quantize = 0;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "O&|p:to_vox", kwlist, PyUnicode_FSConverter, &pathobj, &quantize)) return NULL;
    const char* path = PyBytes_AS_STRING(pathobj);
    vx_error err = {0};
    vx_vox_scene v;
    vx_conv_vox_export_stats st = {0};
    vx_result r = vx_conv_svo_to_vox_ex(&(vx_conv_vox_export_desc){.quantize = quantize}, &self->s, &v, &st, &err);
    if (r == VX_OK) {
        r = vx_vox_write_file(NULL, &v, path, &err);
        vx_vox_scene_free(&v);
    }
    if (r == VX_ERR_UNSUPPORTED && st.colors > 255) /* the library names its desc field; name the keyword */
        snprintf(err.msg + strlen(err.msg), sizeof err.msg - strlen(err.msg), " (to_vox(path, quantize=True))");
    PyObject* out = r == VX_OK ? Py_NewRef(Py_None) : raise_error(path, &err);
    if (out && st.quantized) {
        char msg[1280]; /* PyErr_WarnFormat has no %f */
        snprintf(msg, sizeof msg,
                 "%s: %u distinct colours quantized to a 255-entry palette: colour error (RGBA distance, 0-255 a channel) "
                 "max %.2f, mean %.2f", path, st.colors, st.max_error, st.mean_error);
        if (PyErr_WarnEx(vx_py_quantize_warning, msg, 1) < 0) Py_CLEAR(out); /* the filters made it an exception */
    }
    Py_DECREF(pathobj);
    return out;
}

#ifdef VX_PY_RENDER
/* Reads an optional sequence of 3 numbers into v; returns 0, 1 (given) or -1. */
static int vec3(PyObject* o, const char* name, double v[3]) {
    if (!o || o == Py_None) return 0;
    PyObject* f = PySequence_Fast(o, "must be a sequence");
    if (!f) return -1;
    if (PySequence_Fast_GET_SIZE(f) != 3) {
        Py_DECREF(f);
        PyErr_Format(PyExc_ValueError, "%s must have 3 numbers", name);
        return -1;
    }
    for (int i = 0; i < 3; i++) v[i] = PyFloat_AsDouble(PySequence_Fast_GET_ITEM(f, i));
    Py_DECREF(f);
    return PyErr_Occurred() ? -1 : 1;
}

static PyObject* scene_render(Scene* self, PyObject* args, PyObject* kw) {
    static char* kwlist[] = {"width", "height", "mode", "spp", "eye", "target", "up", "fov", "ortho",
                             "ortho_height", "cpu", "device", NULL};
    unsigned int width = 0, height = 0, spp = 0;
    const char* mode = "color";
    PyObject *eye = NULL, *target = NULL, *up = NULL;
    double fov = 0, ortho_height = 0;
    int ortho = 0, cpu = 0;
    const char* device = NULL;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "|IIsIOOOdpdpz:render", kwlist, &width, &height, &mode, &spp, &eye,
                                     &target, &up, &fov, &ortho, &ortho_height, &cpu, &device))
        return NULL;
    vx_render_desc d = {.width = width, .height = height, .spp = spp};
    if (!vx_render_mode_parse(mode, &d.mode)) return PyErr_Format(PyExc_ValueError, "unknown render mode '%s'", mode);
    int ge = vec3(eye, "eye", d.camera.eye), gt = vec3(target, "target", d.camera.target);
    if (ge < 0 || gt < 0 || vec3(up, "up", d.camera.up) < 0) return NULL;
    if (ge != gt) return PyErr_Format(PyExc_ValueError, "eye and target go together");
    d.camera.set = ge == 1;
    d.camera.fov = fov;
    d.camera.ortho = ortho;
    d.camera.ortho_height = ortho_height;
    vx_error err = {0};
    if (vx_render_desc_validate(&d, &err) != VX_OK) {
        PyErr_SetString(PyExc_ValueError, err.msg);
        return NULL;
    }
    vx_render_image img = {0};
    vx_result r = VX_OK;
    const char* dev = device ? device : "";
    Py_BEGIN_ALLOW_THREADS
    if (cpu) r = vx_render_cpu(&self->s, &d, NULL, &img, &err);
    else {
        PyThread_acquire_lock(self->lock, WAIT_LOCK);
        if (self->gpu && strcmp(self->device, dev)) { /* another device asked for */
            vx_render_scene_destroy(self->rs);
            vx_gpu_destroy(self->gpu);
            free(self->device);
            self->rs = NULL, self->gpu = NULL, self->device = NULL;
        }
        if (!self->gpu) {
            self->device = strdup(dev);
            r = self->device ? vx_gpu_create(&(vx_gpu_desc){.device = dev}, &self->gpu, &err)
                             : vx_fail(&err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
        }
        if (r == VX_OK && !self->rs) r = vx_render_scene_create(self->gpu, &self->s, &self->rs, &err);
        if (r == VX_OK) r = vx_render_frame(self->rs, &d, &img, &err);
        if (!self->gpu) { /* creation failed */
            free(self->device);
            self->device = NULL;
        }
        PyThread_release_lock(self->lock);
    }
    Py_END_ALLOW_THREADS
    if (r != VX_OK) return raise_error(NULL, &err);
    npy_intp dims[3] = {img.height, img.width, 4};
    PyObject* a = PyArray_SimpleNew(3, dims, NPY_FLOAT32);
    if (a) memcpy(PyArray_DATA((PyArrayObject*)a), img.pixels, sizeof(float) * 4 * (size_t)img.width * img.height);
    vx_render_image_free(&img);
    return a;
}
#endif

/* to_glb / to_vdb: the library's exports (convert/export.h), of the scene
 * or of one animation frame's view, as svo_info --to-glb / --to-vdb write
 * them (the same bytes for a .glb). */
static PyObject* export_file(Scene* self, PyObject* pathobj, bool glb, vx_conv_export_desc desc, unsigned int frame) {
    vx_svo_scene view;
    if (!frame_view(self, frame, &view)) {
        Py_DECREF(pathobj);
        return NULL;
    }
    const char* path = PyBytes_AS_STRING(pathobj);
    vx_error err = {0};
    vx_result r;
    desc.svo_path = self->path;
    Py_BEGIN_ALLOW_THREADS
    r = glb ? vx_conv_svo_to_glb_file(&desc, &view, path, NULL, &err) : vx_conv_svo_to_vdb_file(&desc, &view, path, NULL, &err);
    Py_END_ALLOW_THREADS
    PyObject* out = r == VX_OK ? Py_NewRef(Py_None) : raise_error(path, &err);
    Py_DECREF(pathobj);
    return out;
}

static PyObject* scene_to_glb(Scene* self, PyObject* args, PyObject* kw) {
    static char* kwlist[] = {"path", "all", "frame", NULL};
    PyObject* pathobj;
    int all = 0;
    unsigned int frame = 0;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "O&|pI:to_glb", kwlist, PyUnicode_FSConverter, &pathobj, &all, &frame))
        return NULL;
    return export_file(self, pathobj, true, (vx_conv_export_desc){.all = all}, frame);
}

static PyObject* scene_to_vdb(Scene* self, PyObject* args, PyObject* kw) {
    static char* kwlist[] = {"path", "all", "models", "frame", NULL};
    PyObject* pathobj;
    int all = 0, models = 0;
    unsigned int frame = 0;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "O&|ppI:to_vdb", kwlist, PyUnicode_FSConverter, &pathobj, &all, &models,
                                     &frame))
        return NULL;
    return export_file(self, pathobj, false, (vx_conv_export_desc){.all = all, .vdb_models = models}, frame);
}

static PyMethodDef scene_methods[] = {
    {"voxels", (PyCFunction)scene_voxels, METH_VARARGS,
     "voxels(model) -> (xyz, rgba): the model's cells as an (N,3) int32 array of model cells and their\n"
     "colours as an (N,4) uint8 array (sRGB RGBA; palette looked up; white without attributes),\n"
     "in Morton order."},
    {"scene_voxels", (PyCFunction)(void (*)(void))scene_scene_voxels, METH_VARARGS | METH_KEYWORDS,
     "scene_voxels(all=False) -> (xyz, rgba): every visible instance's cells in grid cells\n"
     "(floor(M (v + 1/2) + t)) as (N,3) int64, with (N,4) uint8 colours: what `svo_info --dump`\n"
     "prints. all=True includes hidden instances and layers. frame=N: an animation's frame N\n"
     "(svo_info --dump --frame N)."},
    {"frame_instances", (PyCFunction)scene_frame_instances, METH_VARARGS,
     "frame_instances(n) -> the instances of animation frame n (as `instances`: model, xform, hidden,\n"
     "visible are the frame's; instance i of every frame is the same object, its model and transform\n"
     "may change). Frame 0 is `instances`; a static scene has frame 0 only."},
    {"save", (PyCFunction)scene_save, METH_VARARGS, "save(path): writes the scene as a .svo file."},
    {"to_vox", (PyCFunction)(void (*)(void))scene_to_vox, METH_VARARGS | METH_KEYWORDS,
     "to_vox(path, quantize=False): writes the scene as a MagicaVoxel .vox file (as svo_info --to-vox).\n"
     "A .vox palette holds 255 colours: a scene with more raises voxkit.Error, unless quantize=True\n"
     "maps them to a 255-entry palette (median cut, each cell its nearest entry; svo_info --quantize)\n"
     "and warns with voxkit.QuantizeWarning giving the count and the colour error (max, mean)."},
    {"to_glb", (PyCFunction)(void (*)(void))scene_to_glb, METH_VARARGS | METH_KEYWORDS,
     "to_glb(path, all=False, frame=0): writes the scene as binary glTF (as svo_info --to-glb): one\n"
     "mesh per model (greedy-meshed surface, vertex colours), one node per shown instance, turned\n"
     "to glTF's +Y up; MATL metal, glass and emission as glTF materials, the lights as\n"
     "KHR_lights_punctual (voxkit's exact record in their extras). all=True: hidden\n"
     "instances and layers too; frame=N: an animation's frame N."},
    {"to_vdb", (PyCFunction)(void (*)(void))scene_to_vdb, METH_VARARGS | METH_KEYWORDS,
     "to_vdb(path, all=False, models=False, frame=0): writes the scene as OpenVDB grids (as\n"
     "svo_info --to-vdb): the flattened scene as a fog volume 'density' and a vec3 grid 'color'\n"
     "(linear RGB); models=True: a grid pair 'NAME/density', 'NAME/color' per shown instance\n"
     "(svo_info --vdb-models)."},
#ifdef VX_PY_RENDER
    {"render", (PyCFunction)(void (*)(void))scene_render, METH_VARARGS | METH_KEYWORDS,
     "render(width=640, height=480, mode='color', spp=1, eye=None, target=None, up=None, fov=45,\n"
     "       ortho=False, ortho_height=0, cpu=False, device=None) -> (H,W,4) float32 array\n"
     "Renders through the Vulkan tracer (lavapipe without a GPU; device: an index or part of a\n"
     "name) or, with cpu=True, the double-precision CPU reference. Modes: color, albedo, normal,\n"
     "depth (world t, inf for a miss), instance, iterations. Row 0 is the top. Without eye and\n"
     "target the scene bounds are framed (render/render.h)."},
#endif
    {NULL, NULL, 0, NULL}};

static PyGetSetDef scene_getset[] = {
    {"models", (getter)scene_models, NULL, "list of dicts: size, depth, voxel_count, attrs", NULL},
    {"instances", (getter)scene_instances, NULL,
     "list of dicts: model, name, layer, xform (3x4 model cells -> grid cells), world (3x4 model\n"
     "cells -> world units), hidden, visible",
     NULL},
    {"frame_count", (getter)scene_frame_count, NULL, "animation frames (1 for a static scene)", NULL},
    {"frame_rate", (getter)scene_frame_rate, NULL, "frames per second, 0.0 where the source does not say", NULL},
    {"world_from_grid", (getter)scene_world_from_grid, NULL, "3x4 map from grid cells to world units", NULL},
    {"bounds", (getter)scene_bounds, NULL, "world bounds (lo, hi) of the drawn instances", NULL},
    {"sky", (getter)scene_get_sky, (setter)scene_set_sky,
     "the sky stored in the scene, as svo_render --sky's text: 'R,G,B', 'gradient:ZENITH:HORIZON:GROUND'\n"
     "(R,G,B each) or 'map:FILE[:INTENSITY[:ROTATION]]' (degrees); None for the renderer's own sky.\n"
     "Assign such a text to set it (ValueError saying what is wrong when it is not one), None, 'default'\n"
     "or del to reset it; save() writes it. A map's FILE is read and given from the current folder and\n"
     "stored from the scene file's (as vox2svo --sky stores it).",
     NULL},
    {NULL, NULL, NULL, NULL, NULL}};

static PyTypeObject SceneType = {
    PyVarObject_HEAD_INIT(NULL, 0).tp_name = "voxkit.Scene",
    .tp_basicsize = sizeof(Scene),
    .tp_dealloc = (destructor)scene_dealloc,
    .tp_flags = Py_TPFLAGS_DEFAULT,
    .tp_doc = "A voxkit scene: models (one octree each) placed by instances. Made by voxkit.open().",
    .tp_methods = scene_methods,
    .tp_getset = scene_getset,
};

/* ---- module functions ------------------------------------------------------------- */

/* Converter options from keywords (names as the tools' options, with _). */
static int conv_options(PyObject* kw, vx_conv_file_desc* d) {
    *d = vx_conv_file_defaults();
    if (!kw) return 0;
    PyObject *key, *val;
    Py_ssize_t pos = 0;
    while (PyDict_Next(kw, &pos, &key, &val)) {
        const char* k = PyUnicode_AsUTF8(key);
        if (!k) return -1;
        bool* flag = !strcmp(k, "keep_hidden")   ? &d->keep_hidden
                     : !strcmp(k, "keep_unused") ? &d->keep_unused
                     : !strcmp(k, "normals")     ? &d->normals
                     : !strcmp(k, "no_color")    ? &d->no_color
                     : !strcmp(k, "solid")       ? &d->solid
                     : !strcmp(k, "density")     ? &d->density
                     : !strcmp(k, "no_collapse") ? &d->build.no_collapse
                     : !strcmp(k, "no_dag")      ? &d->build.no_dag
                     : !strcmp(k, "y_up")        ? &d->y_up
                                                 : NULL;
        uint32_t* u = !strcmp(k, "frame") ? &d->frame : !strcmp(k, "res") ? &d->res : !strcmp(k, "threads") ? &d->threads
                                                      : !strcmp(k, "scene") ? &d->scene : NULL;
        if (flag) {
            int t = PyObject_IsTrue(val);
            if (t < 0) return -1;
            *flag = t;
        } else if (u) {
            unsigned long v = PyLong_AsUnsignedLong(val);
            if (PyErr_Occurred()) return -1;
            if (v > UINT32_MAX || (!strcmp(k, "res") && (v < 1 || v > 65536))) {
                PyErr_Format(PyExc_ValueError, "bad %s value %lu", k, v);
                return -1;
            }
            *u = (uint32_t)v;
            if (u == &d->scene) d->scene_set = true;
        } else if (!strcmp(k, "threshold")) {
            d->threshold = PyFloat_AsDouble(val);
            if (PyErr_Occurred()) return -1;
            d->threshold_set = true;
        } else if (!strcmp(k, "grid") || !strcmp(k, "color_grid")) {
            const char* s = PyUnicode_AsUTF8(val); /* kept alive by the kwargs dict */
            if (!s) return -1;
            if (!strcmp(k, "grid")) d->grid = s;
            else d->color_grid = s;
        } else {
            PyErr_Format(PyExc_TypeError, "unknown converter option '%s'", k);
            return -1;
        }
    }
    return 0;
}

/* Loads path into a new Scene (converting by extension). */
static Scene* load(const char* path, PyObject* kw) {
    vx_conv_file_desc d;
    if (conv_options(kw, &d)) return NULL;
    d.allow_svo = true;
    Scene* self = PyObject_New(Scene, &SceneType);
    if (!self) return NULL;
    self->loaded = false;
    self->path = NULL;
#ifdef VX_PY_RENDER
    self->gpu = NULL, self->rs = NULL, self->device = NULL;
    self->lock = PyThread_allocate_lock();
    if (!self->lock) {
        Py_DECREF(self);
        PyErr_NoMemory();
        return NULL;
    }
#endif
    vx_error err = {0};
    vx_result r;
    Py_BEGIN_ALLOW_THREADS
    r = vx_conv_file(&d, path, &self->s, NULL, &err);
    Py_END_ALLOW_THREADS
    if (r != VX_OK) {
        Py_DECREF(self);
        raise_error(path, &err);
        return NULL;
    }
    self->loaded = true;
    self->path = strdup(path); /* NULL (out of memory) only loses the map path's folder: written as it is */
    return self;
}

static PyObject* py_open(PyObject* mod, PyObject* args, PyObject* kw) {
    (void)mod;
    PyObject* pathobj;
    if (!PyArg_ParseTuple(args, "O&:open", PyUnicode_FSConverter, &pathobj)) return NULL;
    Scene* s = load(PyBytes_AS_STRING(pathobj), kw);
    Py_DECREF(pathobj);
    return (PyObject*)s;
}

static PyObject* py_convert(PyObject* mod, PyObject* args, PyObject* kw) {
    (void)mod;
    PyObject *src, *dst;
    if (!PyArg_ParseTuple(args, "O&O&:convert", PyUnicode_FSConverter, &src, PyUnicode_FSConverter, &dst)) return NULL;
    Scene* s = load(PyBytes_AS_STRING(src), kw);
    PyObject* out = NULL;
    if (s) {
        const char* path = PyBytes_AS_STRING(dst);
        vx_error err = {0};
        vx_result r;
        Py_BEGIN_ALLOW_THREADS
        r = write_svo(&s->s, PyBytes_AS_STRING(src), path, &err);
        Py_END_ALLOW_THREADS
        if (r == VX_OK) out = (PyObject*)s;
        else {
            Py_DECREF(s);
            raise_error(path, &err);
        }
    }
    Py_DECREF(src);
    Py_DECREF(dst);
    return out;
}

static PyMethodDef module_methods[] = {
    {"open", (PyCFunction)(void (*)(void))py_open, METH_VARARGS | METH_KEYWORDS,
     "open(path, **options) -> Scene\n"
     "Reads a .svo file, or converts a .vox, .gltf/.glb or .vdb file by its extension. Options\n"
     "(convert/file.h; the tools' options with _): frame, keep_hidden, keep_unused (.vox); res\n"
     "(default 256), scene, solid, normals, no_color, threads, y_up (glTF); grid, solid, threshold,\n"
     "density, color_grid (.vdb); no_collapse, no_dag (all). Raises voxkit.Error."},
    {"convert", (PyCFunction)(void (*)(void))py_convert, METH_VARARGS | METH_KEYWORDS,
     "convert(src, dst, **options) -> Scene\n"
     "open(src, **options), then writes the scene to the .svo file dst (as vox2svo does)."},
    {NULL, NULL, 0, NULL}};

static struct PyModuleDef voxkit_module = {
    PyModuleDef_HEAD_INIT, "voxkit",
    "voxkit: voxel scenes (.svo, .vox, glTF, OpenVDB) as numpy arrays, over the C library libvoxkit.",
    -1, module_methods, NULL, NULL, NULL, NULL};

PyMODINIT_FUNC PyInit_voxkit(void) {
    import_array();
    if (PyType_Ready(&SceneType) < 0) return NULL;
    PyObject* m = PyModule_Create(&voxkit_module);
    if (!m) return NULL;
    vx_py_error = PyErr_NewExceptionWithDoc(
        "voxkit.Error", "A voxkit call failed: the message is voxkit's, naming the file; attributes path, code, offset.",
        PyExc_Exception, NULL);
    vx_py_quantize_warning = PyErr_NewExceptionWithDoc(
        "voxkit.QuantizeWarning",
        "Scene.to_vox(quantize=True) mapped more than 255 colours to a 255-entry palette: the message gives the count "
        "and the colour error.",
        PyExc_UserWarning, NULL);
    if (!vx_py_error || !vx_py_quantize_warning || PyModule_AddObjectRef(m, "Error", vx_py_error) < 0 ||
        PyModule_AddObjectRef(m, "QuantizeWarning", vx_py_quantize_warning) < 0 ||
        PyModule_AddObjectRef(m, "Scene", (PyObject*)&SceneType) < 0 ||
        PyModule_AddStringConstant(m, "__version__", vx_version()) < 0 ||
        PyModule_AddIntConstant(m, "has_render",
#ifdef VX_PY_RENDER
                                1
#else
                                0
#endif
                                ) < 0) {
        Py_DECREF(m);
        return NULL;
    }
    return m;
}
