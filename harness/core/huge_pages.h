// An allocator for large read-mostly tables that are read at scattered places (the exact
// tracer's texels and maximum mipmap): blocks of 256 KiB and more are rounded up to whole
// 2 MiB pages, aligned to 2 MiB and, on Linux, marked MADV_HUGEPAGE before their first touch,
// so that the kernel backs them with transparent huge pages where it can (with THP in
// "madvise" mode, the common default, it does so only for memory marked this way). Smaller blocks,
// and every block where the advice is refused, are ordinary memory: the contents never depend on
// it, only the number of TLB misses does. Embree does the same for its BVH on Linux (its device
// option "hugepages", on by default there: RenderKit/embree kernels/common/state.cpp, State::State,
// commit 0019193c6c073ebc8f0ae7df69442ba914953f72).
#pragma once
#include <cstddef>
#include <cstdlib>
#include <new>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace pxh {

template <typename T>
struct HugePageAllocator {
    using value_type = T;
    static constexpr size_t kHuge = size_t(2) << 20;  // 2 MiB, x86-64's huge page
    static constexpr size_t kLarge = size_t(256) << 10;
    HugePageAllocator() = default;
    template <typename U>
    HugePageAllocator(const HugePageAllocator<U>&) {}
    T* allocate(size_t n) {
        const size_t bytes = n * sizeof(T);
        void* p = nullptr;
        if (bytes >= kLarge) {
            const size_t rounded = (bytes + kHuge - 1) / kHuge * kHuge;
            p = std::aligned_alloc(kHuge, rounded);
#if defined(__linux__) && defined(MADV_HUGEPAGE)
            if (p) madvise(p, rounded, MADV_HUGEPAGE);  // advice only: ignored where refused
#endif
        } else {
            p = std::malloc(bytes > 0 ? bytes : 1);
        }
        if (!p) throw std::bad_alloc();
        return static_cast<T*>(p);
    }
    void deallocate(T* p, size_t) { std::free(p); }
    template <typename U>
    bool operator==(const HugePageAllocator<U>&) const {
        return true;
    }
    template <typename U>
    bool operator!=(const HugePageAllocator<U>&) const {
        return false;
    }
};

template <typename T>
using HugePageVector = std::vector<T, HugePageAllocator<T>>;

}  // namespace pxh
