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
//
// It also reclaims OpenVDB's one known leak for the fuzz target
// (vdb_new_guard.h): RootNode::readTopology holds the child node it is reading
// in a raw pointer, so when a garbled file makes that read throw, the child
// and everything read below it leak (upstream, not fixable from the shim: a
// half-read node holds garbage child pointers and cannot be deleted). The
// fuzz target lost 0.3-6 MB per such input, most mutations of a small file,
// and could not run long. Every block carries a small header that links it
// into a list while tracking is on; what is still in the list when the
// target's call returns is exactly what operator new handed out during the
// call and nobody freed. Our own code allocates with malloc (the shim's C++
// objects are freed before the call returns), so LeakSanitizer still sees
// every leak of ours. Only blocks that code of this executable or of
// libopenvdb asks for are listed (the caller's address): libraries that
// allocate for good on first use, in whatever call that is (TBB's task
// scheduler, log4cplus), are left alone; their blocks were once reclaimed
// and used after (the second campaign's job, in TBB's parallel_reduce).
#include "vdb_new_guard.h"

#include <link.h>

#include <atomic>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <new>

namespace {
constexpr std::size_t kMaxAlloc = std::size_t(1) << 33; // 8 GiB: more than this machine has

struct alignas(16) Head {
    Head* prev;
    Head* next; // both null: not tracked
    std::size_t magic;
    std::size_t pad;
};
static_assert(sizeof(Head) == 32, "keeps malloc's 16-byte alignment");
constexpr std::size_t kMagic = 0x76786e6577677561u;

std::atomic<bool> g_tracking{false};
std::mutex g_lock;
Head g_list{&g_list, &g_list, kMagic, 0}; // circular, sentinel

// The executable segments of this program and of libopenvdb, found once.
struct Range {
    std::uintptr_t lo, hi;
};
Range g_code[16];
int g_ncode = -1;

int add_code(dl_phdr_info* info, size_t, void*) {
    const char* name = info->dlpi_name;
    if (name && *name && !std::strstr(name, "libopenvdb")) return 0;
    for (int i = 0; i < info->dlpi_phnum && g_ncode < 16; i++) {
        const ElfW(Phdr)& ph = info->dlpi_phdr[i];
        if (ph.p_type != PT_LOAD || !(ph.p_flags & PF_X)) continue;
        const std::uintptr_t lo = info->dlpi_addr + ph.p_vaddr;
        g_code[g_ncode++] = Range{lo, lo + ph.p_memsz};
    }
    return 0;
}

bool ours(const void* caller) {
    const std::uintptr_t a = reinterpret_cast<std::uintptr_t>(caller);
    for (int i = 0; i < g_ncode; i++)
        if (a >= g_code[i].lo && a < g_code[i].hi) return true;
    return false;
}

void* raw(std::size_t n, const void* caller) noexcept {
    if (n > kMaxAlloc) return nullptr;
    Head* h = static_cast<Head*>(std::malloc(sizeof(Head) + (n ? n : 1)));
    if (!h) return nullptr;
    h->prev = h->next = nullptr;
    h->magic = kMagic;
    h->pad = 0;
    if (g_tracking.load(std::memory_order_relaxed) && ours(caller)) {
        std::lock_guard<std::mutex> l(g_lock);
        h->prev = &g_list;
        h->next = g_list.next;
        g_list.next->prev = h;
        g_list.next = h;
    }
    return h + 1;
}

void release(void* p) noexcept {
    if (!p) return;
    Head* h = static_cast<Head*>(p) - 1;
    if (h->next) {
        std::lock_guard<std::mutex> l(g_lock);
        h->prev->next = h->next;
        h->next->prev = h->prev;
    }
    std::free(h);
}

void* guarded(std::size_t n, const void* caller) {
    void* p = raw(n, caller);
    if (!p) throw std::bad_alloc();
    return p;
}
} // namespace

extern "C" void vx_test_new_track(bool on) {
    if (on && g_ncode < 0) {
        g_ncode = 0;
        dl_iterate_phdr(add_code, nullptr);
    }
    g_tracking.store(on, std::memory_order_relaxed);
}

static std::size_t drain(bool free_them) {
    std::lock_guard<std::mutex> l(g_lock);
    std::size_t n = 0;
    while (g_list.next != &g_list) {
        Head* h = g_list.next;
        g_list.next = h->next;
        if (free_them) {
            std::free(h);
        } else {
            h->prev = h->next = nullptr;
        }
        n++;
    }
    g_list.prev = &g_list;
    return n;
}

extern "C" std::size_t vx_test_new_reclaim(void) { return drain(true); }
extern "C" std::size_t vx_test_new_forget(void) { return drain(false); }

// __builtin_return_address(0): the code that asked (inline allocators
// included, which are compiled into their caller's module)
void* operator new(std::size_t n) { return guarded(n, __builtin_return_address(0)); }
void* operator new[](std::size_t n) { return guarded(n, __builtin_return_address(0)); }
void* operator new(std::size_t n, const std::nothrow_t&) noexcept { return raw(n, __builtin_return_address(0)); }
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept { return raw(n, __builtin_return_address(0)); }
void operator delete(void* p) noexcept { release(p); }
void operator delete[](void* p) noexcept { release(p); }
void operator delete(void* p, std::size_t) noexcept { release(p); }
void operator delete[](void* p, std::size_t) noexcept { release(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { release(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { release(p); }
