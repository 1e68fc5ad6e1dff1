// An allocator for the big arrays (fields, FFT buffers) that asks Linux for transparent huge
// pages (2 MiB) where the array is large enough to fill some.
//
// The sweeps stream several fields at once and the FFT strides across whole planes; with
// 4 KiB pages every plane of a 128^3 field is 32 pages, and the strided passes miss the TLB
// on most accesses. Debian's kernels leave transparent huge pages to `madvise` (the
// default of /sys/kernel/mm/transparent_hugepage/enabled), so nothing gets them unless the
// program asks. Arrays of at least `threshold` bytes are aligned to 2 MiB and advised
// MADV_HUGEPAGE; smaller ones come from operator new, aligned to a cache line (64 bytes,
// which also suits FFTW's SIMD codelets). The advice is a hint: where
// the kernel has no huge pages (or THP is "never") the array simply keeps 4 KiB pages, and
// values are the same either way (docs/method.md, "Huge pages").
#pragma once

#include <cstddef>
#include <cstdlib>
#include <new>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace efsi {

template <class T>
struct LargePageAllocator {
    using value_type = T;
    static constexpr std::size_t page = std::size_t(2) << 20;
    static constexpr std::size_t threshold = page;
    static constexpr std::align_val_t line{64};

    LargePageAllocator() noexcept = default;
    template <class U>
    LargePageAllocator(const LargePageAllocator<U>&) noexcept {}

    T* allocate(std::size_t n) {
        if (n > std::size_t(-1) / sizeof(T)) throw std::bad_array_new_length();
        const std::size_t bytes = n * sizeof(T);
        if (bytes < threshold) return static_cast<T*>(::operator new(bytes, line));
        const std::size_t rounded = (bytes + page - 1) / page * page;
        void* p = std::aligned_alloc(page, rounded);
        if (!p) throw std::bad_alloc();
#if defined(__linux__) && defined(MADV_HUGEPAGE)
        ::madvise(p, rounded, MADV_HUGEPAGE); // a hint; failure leaves normal pages
#endif
        return static_cast<T*>(p);
    }

    void deallocate(T* p, std::size_t n) noexcept {
        if (n * sizeof(T) < threshold)
            ::operator delete(p, line);
        else
            std::free(p);
    }

    template <class U>
    bool operator==(const LargePageAllocator<U>&) const noexcept {
        return true;
    }
};

} // namespace efsi
