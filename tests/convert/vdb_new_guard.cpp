// tests/convert/vdb_new_guard.cpp - linked into the VDB test executables.
//
// OpenVDB sizes some buffers straight from file fields (bloscFromStream's
// compressed byte count, for one). In a normal build a garbled size makes
// operator new throw std::bad_alloc, which the shim returns as
// VX_ERR_NOMEM. Under ASan, a throwing operator new cannot fail softly
// (allocator_may_return_null only covers malloc): it aborts the process. This
// replacement restores the release behaviour for absurd sizes so the tests
// see what users see; everything else goes to malloc/free (still checked by
// ASan).
#include <cstdlib>
#include <new>

namespace {
constexpr std::size_t kMaxAlloc = std::size_t(1) << 33; // 8 GiB: more than this machine has

void* guarded(std::size_t n) {
    if (n > kMaxAlloc) throw std::bad_alloc();
    void* p = std::malloc(n ? n : 1);
    if (!p) throw std::bad_alloc();
    return p;
}
} // namespace

void* operator new(std::size_t n) { return guarded(n); }
void* operator new[](std::size_t n) { return guarded(n); }
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
    return n > kMaxAlloc ? nullptr : std::malloc(n ? n : 1);
}
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept {
    return n > kMaxAlloc ? nullptr : std::malloc(n ? n : 1);
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }
