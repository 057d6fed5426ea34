// formats/vdb_openvdb.cpp - the C shim over OpenVDB declared in formats/vdb.h.
//
// Kept to one translation unit because OpenVDB headers are slow and memory
// hungry to compile. Every entry point catches all C++ exceptions: nothing
// may unwind into C callers, and nothing is printed.
#include "formats/vdb.h"
#include "formats/vdb_scan.h"

#include <openvdb/io/Compression.h>
#include <openvdb/io/Stream.h>
#include <openvdb/openvdb.h>

#include <blosc.h>
#include <zlib.h>

#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <istream>
#include <limits>
#include <memory>
#include <mutex>
#include <new>
#include <streambuf>
#include <string>
#include <vector>

// ---- corrected chunk readers ------------------------------------------------
//
// OpenVDB 10.0.1 (Debian 12) bloscFromStream reads an uncompressed chunk of
// the size the file declares *before* comparing it with the destination
// size, so a crafted negative size overflows the heap (found by the
// vdb_fuzz replay under ASan; later upstream releases check first). These
// definitions interpose the library's exported ones (ELF symbol
// interposition: the executable's definition wins for every caller,
// including libopenvdb itself), and check every declared size against the
// destination before anything is written.
namespace openvdb {
OPENVDB_USE_VERSION_NAMESPACE
namespace OPENVDB_VERSION_NAME {
namespace io {

namespace {
Int64 read_chunk_size(std::istream& is, const char* kind) {
    Int64 n = 0;
    is.read(reinterpret_cast<char*>(&n), 8);
    if (!is.good()) OPENVDB_THROW(RuntimeError, std::string("stream failure reading the size of a ") + kind + " chunk");
    return n;
}

// A compressed chunk cannot be longer than what is left of the stream:
// checked before the chunk is allocated, so a garbled size fails cleanly
// instead of asking for petabytes.
void check_chunk_fits(std::istream& is, Int64 n, const char* kind) {
    const std::streampos here = is.tellg();
    if (here == std::streampos(-1)) return; // size unknown: the read itself fails
    is.seekg(0, std::ios_base::end);
    const std::streampos end = is.tellg();
    is.seekg(here);
    if (end != std::streampos(-1) && n > static_cast<Int64>(end - here))
        OPENVDB_THROW(RuntimeError, std::string(kind) + " chunk of " + std::to_string(n) + " bytes, " +
                                        std::to_string(static_cast<Int64>(end - here)) + " left in the file");
}

// A non-positive size marks an uncompressed chunk of -n bytes.
void read_raw_chunk(std::istream& is, char* data, size_t numBytes, Int64 n, const char* kind) {
    if (n == std::numeric_limits<Int64>::min() || static_cast<uint64_t>(-n) != numBytes)
        OPENVDB_THROW(RuntimeError, std::string("uncompressed ") + kind + " chunk of " + std::to_string(-n) +
                                        " bytes where " + std::to_string(numBytes) + " are expected");
    if (data) is.read(data, -n);
    else is.seekg(-n, std::ios_base::cur);
}

// The part both chunk kinds share: size, uncompressed or skipped chunks, and
// the bounds check before the compressed bytes are read into *src. Returns
// their count, or 0 when there is nothing left to decompress.
Int64 read_compressed(std::istream& is, char* data, size_t numBytes, const char* kind, std::unique_ptr<char[]>* src) {
    const Int64 n = read_chunk_size(is, kind);
    if (n <= 0) {
        read_raw_chunk(is, data, numBytes, n, kind);
        return 0;
    }
    if (!data) {
        is.seekg(n, std::ios_base::cur);
        return 0;
    }
    check_chunk_fits(is, n, kind);
    src->reset(new char[static_cast<size_t>(n)]);
    is.read(src->get(), n);
    return n;
}
} // namespace

void bloscFromStream(std::istream& is, char* data, size_t numBytes) {
    std::unique_ptr<char[]> src;
    const Int64 n = read_compressed(is, data, numBytes, "blosc", &src);
    if (n == 0) return;
    size_t nbytes = 0, cbytes = 0, blocksize = 0;
    if (n < BLOSC_MIN_HEADER_LENGTH) OPENVDB_THROW(RuntimeError, "blosc chunk shorter than its header");
    blosc_cbuffer_sizes(src.get(), &nbytes, &cbytes, &blocksize);
    // OpenVDB's writer pads chunks of fewer than 48 bytes to 128 before
    // compressing, so a small destination may come back from a larger chunk.
    const bool padded = numBytes < 48 && nbytes > numBytes && nbytes <= 128;
    if ((nbytes != numBytes && !padded) || cbytes > static_cast<size_t>(n))
        OPENVDB_THROW(RuntimeError, "blosc chunk declares " + std::to_string(nbytes) + " bytes in " +
                                        std::to_string(cbytes) + ", expected " + std::to_string(numBytes) +
                                        " in at most " + std::to_string(n));
    std::unique_ptr<char[]> pad(padded ? new char[nbytes] : nullptr);
    char* dst = padded ? pad.get() : data;
    const int got = blosc_decompress_ctx(src.get(), dst, nbytes, 1);
    if (got < 0 || static_cast<size_t>(got) != nbytes)
        OPENVDB_THROW(RuntimeError, "blosc chunk does not decompress to " + std::to_string(nbytes) + " bytes");
    if (padded) std::memcpy(data, pad.get(), numBytes);
}

void unzipFromStream(std::istream& is, char* data, size_t numBytes) {
    std::unique_ptr<char[]> src;
    const Int64 n = read_compressed(is, data, numBytes, "zip", &src);
    if (n == 0) return;
    uLongf out = static_cast<uLongf>(numBytes);
    const int zr = uncompress(reinterpret_cast<Bytef*>(data), &out, reinterpret_cast<const Bytef*>(src.get()),
                              static_cast<uLong>(n));
    if (zr != Z_OK || out != numBytes)
        OPENVDB_THROW(RuntimeError, "zip chunk does not decompress to " + std::to_string(numBytes) + " bytes");
}

} // namespace io
} // namespace OPENVDB_VERSION_NAME
} // namespace openvdb

namespace {

// A read-only streambuf over caller memory, so files and fuzz inputs share
// one path and nothing is copied. Seeks are bounds-checked in integers.
class MemBuf : public std::streambuf {
public:
    MemBuf(const char* p, size_t n) {
        char* b = const_cast<char*>(p);
        setg(b, b, b + n);
    }
    size_t pos() const { return static_cast<size_t>(gptr() - eback()); }

protected:
    pos_type seekoff(off_type off, std::ios_base::seekdir dir, std::ios_base::openmode) override {
        const off_type size = static_cast<off_type>(egptr() - eback());
        off_type base = 0;
        if (dir == std::ios_base::cur) base = static_cast<off_type>(pos());
        else if (dir == std::ios_base::end) base = size;
        if ((off < 0 && -off > base) || (off > 0 && off > size - base)) return pos_type(off_type(-1));
        setg(eback(), eback() + (base + off), egptr());
        return pos_type(base + off);
    }
    pos_type seekpos(pos_type p, std::ios_base::openmode m) override {
        return seekoff(off_type(p), std::ios_base::beg, m);
    }
};

struct ProbeBase {
    virtual ~ProbeBase() = default;
    virtual void get(const openvdb::Coord& c, double v[3], bool* active, uint32_t* log2dim) = 0;
};

inline void to_double(float x, double v[3]) { v[0] = x; }
inline void to_double(double x, double v[3]) { v[0] = x; }
inline void to_double(const openvdb::Vec3s& x, double v[3]) {
    for (int i = 0; i < 3; i++) v[i] = x[i];
}
inline void to_double(const openvdb::Vec3d& x, double v[3]) {
    for (int i = 0; i < 3; i++) v[i] = x[i];
}

template <class GridT>
struct Probe final : ProbeBase {
    using TreeT = typename GridT::TreeType;
    using RootT = typename TreeT::RootNodeType;
    using Upper = typename RootT::ChildNodeType;
    using Lower = typename Upper::ChildNodeType;
    using Leaf = typename Lower::ChildNodeType;
    static_assert(TreeT::DEPTH == 4, "standard four-level trees only");

    typename GridT::ConstPtr grid;
    typename GridT::ConstAccessor acc;
    explicit Probe(typename GridT::ConstPtr g) : grid(g), acc(g->getConstAccessor()) {}

    void get(const openvdb::Coord& c, double v[3], bool* active, uint32_t* log2dim) override {
        to_double(acc.getValue(c), v);
        if (active) *active = acc.isValueOn(c);
        if (log2dim) {
            // depth: 0 root tile, 1 upper tile, 2 lower tile, 3 leaf voxel, -1 background
            switch (acc.getValueDepth(c)) {
                case 3: *log2dim = 0; break;
                case 2: *log2dim = Leaf::TOTAL; break;
                case 1: *log2dim = Lower::TOTAL; break;
                default: *log2dim = Upper::TOTAL; break;
            }
        }
    }
};

struct Entry {
    openvdb::GridBase::Ptr grid;
    vx_vdb_value_type type = VX_VDB_TYPE_OTHER;
    std::string name;                 // the whole name (vx_vdb_grid_info.name is cut at 127 bytes)
    std::unique_ptr<ProbeBase> probe; // made on first use
};

vx_vdb_value_type classify(const openvdb::GridBase& g) {
    if (g.isType<openvdb::FloatGrid>()) return VX_VDB_TYPE_FLOAT;
    if (g.isType<openvdb::DoubleGrid>()) return VX_VDB_TYPE_DOUBLE;
    if (g.isType<openvdb::Vec3SGrid>()) return VX_VDB_TYPE_VEC3F;
    if (g.isType<openvdb::Vec3DGrid>()) return VX_VDB_TYPE_VEC3D;
    return VX_VDB_TYPE_OTHER;
}

template <class GridT>
void background(const openvdb::GridBase& g, double v[3]) {
    to_double(static_cast<const GridT&>(g).background(), v);
}

template <class GridT>
vx_result iterate_typed(const openvdb::GridBase& gb, uint32_t mode, vx_vdb_value_fn fn, void* user) {
    const GridT& g = static_cast<const GridT&>(gb);
    double v[3] = {0, 0, 0};
    int32_t o[3];
    auto visit = [&](auto it) {
        for (; it; ++it) {
            openvdb::CoordBBox b;
            it.getBoundingBox(b);
            const int32_t dim = b.dim().x();
            uint32_t l = 0;
            while ((int64_t(1) << l) < dim) l++;
            to_double(it.getValue(), v);
            o[0] = b.min().x();
            o[1] = b.min().y();
            o[2] = b.min().z();
            if (!fn(user, o, l, it.isValueOn(), v)) return;
        }
    };
    if (mode == VX_VDB_ITER_ALL) visit(g.tree().cbeginValueAll());
    else visit(g.tree().cbeginValueOn());
    return VX_OK;
}

vx_result fail_msg(vx_error* err, vx_result code, uint64_t off, const char* what, const char* msg) {
    return vx_fail(err, code, off, "%s%s", what, msg);
}

void init_once() {
    static std::once_flag once;
    std::call_once(once, [] { openvdb::initialize(); });
}

// Output to a vx_atomic_file (written to a temporary name, renamed on commit).
class AtomicBuf : public std::streambuf {
  public:
    explicit AtomicBuf(vx_atomic_file* af) : af_(af) {}

  protected:
    std::streamsize xsputn(const char* s, std::streamsize n) override {
        return vx_atomic_write(af_, s, static_cast<size_t>(n)) ? n : 0;
    }
    int_type overflow(int_type c) override {
        if (traits_type::eq_int_type(c, traits_type::eof())) return traits_type::not_eof(c);
        const char ch = traits_type::to_char_type(c);
        return vx_atomic_write(af_, &ch, 1) ? c : traits_type::eof();
    }

  private:
    vx_atomic_file* af_;
};

template <typename GridT, int N>
typename GridT::Ptr make_grid(const vx_vdb_write_grid& w) {
    using V = typename GridT::ValueType;
    typename GridT::Ptr g = GridT::create(V(0));
    auto acc = g->getAccessor();
    for (size_t i = 0; i < w.count; i++) {
        const openvdb::Coord ijk(w.ijk[3 * i], w.ijk[3 * i + 1], w.ijk[3 * i + 2]);
        if constexpr (N == 1) acc.setValueOn(ijk, w.value[i]);
        else acc.setValueOn(ijk, V(w.value[3 * i], w.value[3 * i + 1], w.value[3 * i + 2]));
    }
    return g;
}

} // namespace

struct vx_vdb_file {
    std::vector<Entry> grids;
};

// The arguments of a call on one grid of f (vx_vdb_grid_get_info, vx_vdb_iterate): f and the call's output
// (out_ok: not NULL) given, grid in range.
static vx_result grid_arg(const vx_vdb_file* f, bool out_ok, uint32_t grid, vx_error* err) {
    if (!f || !out_ok) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "vdb: NULL argument");
    if (grid >= f->grids.size())
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "vdb: grid %u out of range (%zu grids)", grid,
                       f->grids.size());
    return VX_OK;
}

extern "C" {

vx_result vx_vdb_read(const void* data, size_t size, vx_vdb_file** out, vx_error* err) {
    if (!out || (!data && size)) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "vdb: NULL argument");
    // OpenVDB allocates what a length says before reading: lengths first
    vx_result sr = vx__vdb_scan(data, size, err);
    if (sr) return sr;
    MemBuf buf(static_cast<const char*>(data), size);
    try {
        init_once();
        std::istream is(&buf);
        // A short read must raise at once: OpenVDB does not check every read,
        // and would otherwise build grids from zero-filled garbage.
        is.exceptions(std::ios_base::failbit | std::ios_base::badbit);
        openvdb::io::Stream stream(is, /*delayLoad=*/false);
        openvdb::GridPtrVecPtr grids = stream.getGrids();
        std::unique_ptr<vx_vdb_file> f(new vx_vdb_file);
        if (grids) {
            for (auto& g : *grids) {
                if (!g) continue;
                Entry e;
                e.grid = g;
                e.type = classify(*g);
                e.name = g->getName();
                f->grids.push_back(std::move(e));
            }
        }
        *out = f.release();
        return VX_OK;
    } catch (const std::bad_alloc&) {
        return vx_fail(err, VX_ERR_NOMEM, buf.pos(), "vdb: out of memory near byte %zu", buf.pos());
    } catch (const std::ios_base::failure&) {
        return vx_fail(err, VX_ERR_TRUNCATED, buf.pos(), "vdb: stream ends or fails at byte %zu of %zu", buf.pos(),
                       size);
    } catch (const openvdb::Exception& e) {
        // OpenVDB's own messages name the problem ("IoError: not a VDB file", ...).
        return fail_msg(err, VX_ERR_BAD_FORMAT, buf.pos(), "vdb: ", e.what());
    } catch (const std::exception& e) {
        return fail_msg(err, VX_ERR_BAD_FORMAT, buf.pos(), "vdb: ", e.what());
    } catch (...) {
        return vx_fail(err, VX_ERR_BAD_FORMAT, buf.pos(), "vdb: unknown error near byte %zu", buf.pos());
    }
}

void vx_vdb_file_free(vx_vdb_file* f) { delete f; }

uint32_t vx_vdb_grid_count(const vx_vdb_file* f) { return f ? static_cast<uint32_t>(f->grids.size()) : 0u; }

const char* vx_vdb_grid_name(const vx_vdb_file* f, uint32_t grid) {
    if (!f || grid >= f->grids.size()) return NULL;
    return f->grids[grid].name.c_str();
}

vx_result vx_vdb_grid_get_info(const vx_vdb_file* f, uint32_t grid, vx_vdb_grid_info* out, vx_error* err) {
    vx_result r = grid_arg(f, out != NULL, grid, err);
    if (r) return r;
    try {
        const Entry& e = f->grids[grid];
        const openvdb::GridBase& g = *e.grid;
        vx_vdb_grid_info info;
        std::memset(&info, 0, sizeof info);
        std::snprintf(info.name, sizeof info.name, "%s", g.getName().c_str());
        std::snprintf(info.type, sizeof info.type, "%s", g.type().c_str());
        info.value_type = e.type;
        info.components = e.type == VX_VDB_TYPE_OTHER ? 0u : (e.type >= VX_VDB_TYPE_VEC3F ? 3u : 1u);
        switch (g.getGridClass()) {
            case openvdb::GRID_LEVEL_SET: info.grid_class = VX_VDB_CLASS_LEVEL_SET; break;
            case openvdb::GRID_FOG_VOLUME: info.grid_class = VX_VDB_CLASS_FOG_VOLUME; break;
            case openvdb::GRID_STAGGERED: info.grid_class = VX_VDB_CLASS_STAGGERED; break;
            default: info.grid_class = VX_VDB_CLASS_UNKNOWN; break;
        }
        info.saved_as_half = g.saveFloatAsHalf();
        const openvdb::math::Transform& xf = g.transform();
        info.linear = xf.isLinear();
        if (info.linear) {
            // OpenVDB multiplies row vectors (p' = p M, translation in row 3);
            // we store the column-vector form.
            const openvdb::Mat4d m = xf.baseMap()->getAffineMap()->getMat4();
            for (int r = 0; r < 3; r++) {
                for (int c = 0; c < 3; c++) info.index_to_world[r * 4 + c] = m(c, r);
                info.index_to_world[r * 4 + 3] = m(3, r);
            }
        }
        const openvdb::Vec3d vs = xf.voxelSize();
        for (int i = 0; i < 3; i++) info.voxel_size[i] = vs[i];
        switch (e.type) {
            case VX_VDB_TYPE_FLOAT: background<openvdb::FloatGrid>(g, info.background); break;
            case VX_VDB_TYPE_DOUBLE: background<openvdb::DoubleGrid>(g, info.background); break;
            case VX_VDB_TYPE_VEC3F: background<openvdb::Vec3SGrid>(g, info.background); break;
            case VX_VDB_TYPE_VEC3D: background<openvdb::Vec3DGrid>(g, info.background); break;
            default: break;
        }
        info.active_voxels = g.activeVoxelCount();
        info.active_tiles = g.baseTree().activeTileCount();
        info.leaf_count = g.baseTree().leafCount();
        const openvdb::CoordBBox b = g.evalActiveVoxelBoundingBox();
        info.empty = b.empty();
        if (!info.empty) {
            for (int i = 0; i < 3; i++) {
                info.bbox_min[i] = b.min()[i];
                info.bbox_max[i] = b.max()[i];
            }
        }
        *out = info;
        return VX_OK;
    } catch (const std::bad_alloc&) {
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "vdb: out of memory");
    } catch (const std::exception& e) {
        return fail_msg(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "vdb: ", e.what());
    } catch (...) {
        return vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "vdb: unknown error");
    }
}

vx_result vx_vdb_iterate(vx_vdb_file* f, uint32_t grid, uint32_t mode, vx_vdb_value_fn fn, void* user,
                         vx_error* err) {
    vx_result r = grid_arg(f, fn != NULL, grid, err);
    if (r) return r;
    try {
        const Entry& e = f->grids[grid];
        switch (e.type) {
            case VX_VDB_TYPE_FLOAT: return iterate_typed<openvdb::FloatGrid>(*e.grid, mode, fn, user);
            case VX_VDB_TYPE_DOUBLE: return iterate_typed<openvdb::DoubleGrid>(*e.grid, mode, fn, user);
            case VX_VDB_TYPE_VEC3F: return iterate_typed<openvdb::Vec3SGrid>(*e.grid, mode, fn, user);
            case VX_VDB_TYPE_VEC3D: return iterate_typed<openvdb::Vec3DGrid>(*e.grid, mode, fn, user);
            default:
                return vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET, "vdb: grid '%s' has unsupported type %s",
                               e.grid->getName().c_str(), e.grid->type().c_str());
        }
    } catch (const std::bad_alloc&) {
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "vdb: out of memory");
    } catch (const std::exception& e) {
        return fail_msg(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "vdb: ", e.what());
    } catch (...) {
        return vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "vdb: unknown error");
    }
}

bool vx_vdb_probe(vx_vdb_file* f, uint32_t grid, const int32_t ijk[3], double value[3], bool* active,
                  uint32_t* log2dim) {
    if (!f || !ijk || !value || grid >= f->grids.size()) return false;
    try {
        Entry& e = f->grids[grid];
        if (!e.probe) {
            switch (e.type) {
                case VX_VDB_TYPE_FLOAT:
                    e.probe.reset(new Probe<openvdb::FloatGrid>(openvdb::gridConstPtrCast<openvdb::FloatGrid>(e.grid)));
                    break;
                case VX_VDB_TYPE_DOUBLE:
                    e.probe.reset(
                        new Probe<openvdb::DoubleGrid>(openvdb::gridConstPtrCast<openvdb::DoubleGrid>(e.grid)));
                    break;
                case VX_VDB_TYPE_VEC3F:
                    e.probe.reset(new Probe<openvdb::Vec3SGrid>(openvdb::gridConstPtrCast<openvdb::Vec3SGrid>(e.grid)));
                    break;
                case VX_VDB_TYPE_VEC3D:
                    e.probe.reset(new Probe<openvdb::Vec3DGrid>(openvdb::gridConstPtrCast<openvdb::Vec3DGrid>(e.grid)));
                    break;
                default: return false;
            }
        }
        value[0] = value[1] = value[2] = 0.0;
        e.probe->get(openvdb::Coord(ijk[0], ijk[1], ijk[2]), value, active, log2dim);
        return true;
    } catch (...) {
        return false;
    }
}

vx_result vx_vdb_write_file(const vx_write_desc* desc, const vx_vdb_write_grid* grids, uint32_t count, const char* path,
                            vx_error* err) {
    if (!path || (!grids && count)) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "vdb: NULL argument");
    for (uint32_t i = 0; i < count; i++) {
        const vx_vdb_write_grid& w = grids[i];
        if (w.value_type != VX_VDB_TYPE_FLOAT && w.value_type != VX_VDB_TYPE_VEC3F)
            return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "vdb: grid %u: only float and vec3f grids are written", i);
        if (w.share >= 0 && (static_cast<uint32_t>(w.share) >= i || grids[w.share].value_type != w.value_type ||
                             grids[w.share].share >= 0))
            return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET,
                           "vdb: grid %u shares grid %d, which is not an earlier unshared grid of its type", i, w.share);
        if (w.share < 0 && w.count && (!w.ijk || !w.value))
            return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "vdb: grid %u: no voxels given", i);
        const double* m = w.index_to_world;
        bool finite = true;
        for (int k = 0; k < 12; k++) finite = finite && std::isfinite(m[k]);
        const double det = m[0] * (m[5] * m[10] - m[6] * m[9]) - m[1] * (m[4] * m[10] - m[6] * m[8]) +
                           m[2] * (m[4] * m[9] - m[5] * m[8]);
        if (!finite || !(std::fabs(det) > 0) || !std::isfinite(det))
            return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "vdb: grid %u: the transform is not finite and invertible",
                           i);
    }
    vx_atomic_file af;
    vx_result r = vx_atomic_open(&af, path, desc ? desc->alloc : NULL, err);
    if (r) return r;
    try {
        init_once();
        openvdb::GridPtrVec out;
        for (uint32_t i = 0; i < count; i++) {
            const vx_vdb_write_grid& w = grids[i];
            openvdb::GridBase::Ptr g;
            if (w.share >= 0) g = out[static_cast<size_t>(w.share)]->copyGrid(); // the same tree, written once
            else if (w.value_type == VX_VDB_TYPE_FLOAT) g = make_grid<openvdb::FloatGrid, 1>(w);
            else g = make_grid<openvdb::Vec3SGrid, 3>(w);
            g->setName(w.name ? w.name : "");
            g->setGridClass(w.grid_class == VX_VDB_CLASS_FOG_VOLUME   ? openvdb::GRID_FOG_VOLUME
                            : w.grid_class == VX_VDB_CLASS_LEVEL_SET ? openvdb::GRID_LEVEL_SET
                                                                      : openvdb::GRID_UNKNOWN);
            // OpenVDB multiplies row vectors: world = (i j k 1) * M.
            openvdb::math::Mat4d M = openvdb::math::Mat4d::identity();
            for (int row = 0; row < 3; row++) {
                for (int col = 0; col < 3; col++) M(col, row) = w.index_to_world[row * 4 + col];
                M(3, row) = w.index_to_world[row * 4 + 3];
            }
            g->setTransform(openvdb::math::Transform::createLinearTransform(M));
            if (w.value_type == VX_VDB_TYPE_VEC3F) g->setVectorType(openvdb::VEC_INVARIANT); // colours
            out.push_back(g);
        }
        AtomicBuf buf(&af);
        std::ostream os(&buf);
        openvdb::io::Stream(os).write(out);
        os.flush();
        if (!os.good()) {
            vx_atomic_abort(&af);
            return vx_fail(err, VX_ERR_IO, VX_NO_OFFSET, "vdb: cannot write %s", path);
        }
    } catch (const std::bad_alloc&) {
        vx_atomic_abort(&af);
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "vdb: out of memory writing %u grids", count);
    } catch (const std::exception& e) {
        vx_atomic_abort(&af);
        return fail_msg(err, VX_ERR_IO, VX_NO_OFFSET, "vdb: writing failed: ", e.what());
    } catch (...) {
        vx_atomic_abort(&af);
        return vx_fail(err, VX_ERR_IO, VX_NO_OFFSET, "vdb: writing failed");
    }
    return vx_atomic_commit(&af, err);
}

} // extern "C"
