#pragma once
/// An allocator for the few very large arrays of a build that are read at random (the expression
/// pool's nodes and its hash table): blocks of kHugeBlockBytes and more are mapped on their own
/// and asked to be backed by transparent huge pages (madvise MADV_HUGEPAGE), which spares the
/// TLB miss of nearly every probe of a table of hundreds of megabytes. Smaller blocks come from
/// operator new, so small models see no difference (a huge page costs its zeroing up front).

#include <sys/mman.h>

#include <cstddef>
#include <new>

namespace momenta {

constexpr size_t kHugeBlockBytes = size_t{8} << 20;
constexpr size_t kHugePageBytes = size_t{2} << 20;

template <class T>
struct HugePageAllocator {
  using value_type = T;
  HugePageAllocator() = default;
  template <class U>
  HugePageAllocator(const HugePageAllocator<U>&) {}

  T* allocate(size_t n) {
    const size_t bytes = n * sizeof(T);
    if (bytes < kHugeBlockBytes) return static_cast<T*>(::operator new(bytes));
    void* p = mmap(nullptr, Rounded(bytes), PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (p == MAP_FAILED) throw std::bad_alloc();
    madvise(p, Rounded(bytes), MADV_HUGEPAGE);  // advice only: ordinary pages if refused
    return static_cast<T*>(p);
  }
  void deallocate(T* p, size_t n) {
    const size_t bytes = n * sizeof(T);
    if (bytes < kHugeBlockBytes) {
      ::operator delete(p);
    } else {
      munmap(p, Rounded(bytes));
    }
  }

 private:
  static size_t Rounded(size_t bytes) { return (bytes + kHugePageBytes - 1) / kHugePageBytes * kHugePageBytes; }
};

template <class T, class U>
bool operator==(const HugePageAllocator<T>&, const HugePageAllocator<U>&) { return true; }
template <class T, class U>
bool operator!=(const HugePageAllocator<T>&, const HugePageAllocator<U>&) { return false; }

}  // namespace momenta
