#pragma once
/// An allocator for the few very large arrays of a build that are read at random (the expression
/// pool's nodes and its hash table): blocks of kHugeBlockBytes and more are mapped on their own
/// and asked to be backed by transparent huge pages (madvise MADV_HUGEPAGE), which spares the
/// TLB miss of nearly every probe of a table of hundreds of megabytes. Smaller blocks come from
/// operator new, so small models see no difference (a huge page costs its zeroing up front).

#include <sys/mman.h>

#include <cstddef>
#include <cstring>
#include <new>
#include <type_traits>

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

/// A growable array of a trivially copyable T that never copies itself to grow once it is large:
/// below kHugeBlockBytes it lives in operator new memory; from there on in a mapping of its own,
/// advised to be backed by huge pages, that grows with mremap (the kernel moves the page tables;
/// no element is copied, and the old and new arrays never both take memory, as std::vector's
/// doubling makes them). For the expression pool's nodes: a build of a million components makes
/// tens of millions, and the array grows while the rest of the build is at its largest.
template <class T>
class GrowableArray {
  static_assert(std::is_trivially_copyable_v<T>, "elements are moved by copying bytes");

 public:
  GrowableArray() = default;
  /// One owner: copying tens of millions of nodes is never intended, so the pool holding them
  /// cannot be copied either.
  GrowableArray(const GrowableArray&) = delete;
  GrowableArray& operator=(const GrowableArray&) = delete;
  ~GrowableArray() { Release(); }

  void push_back(const T& v) {
    if (size_ == capacity_) Reserve(size_ + 1);
    data_[size_++] = v;
  }
  T& operator[](size_t k) { return data_[k]; }
  const T& operator[](size_t k) const { return data_[k]; }
  size_t size() const { return size_; }

  /// Room for at least `n` elements (capacity doubles, so pushing stays amortised O(1)).
  void Reserve(size_t n) {
    if (n <= capacity_) return;
    size_t want = capacity_ == 0 ? 64 : capacity_;
    while (want < n) want *= 2;
    const size_t bytes = want * sizeof(T);
    if (bytes < kHugeBlockBytes) {
      T* grown = static_cast<T*>(::operator new(bytes));
      if (size_ > 0) std::memcpy(grown, data_, size_ * sizeof(T));
      ::operator delete(data_);
      data_ = grown;
      capacity_ = want;
      return;
    }
    const size_t mapped = (bytes + kHugePageBytes - 1) / kHugePageBytes * kHugePageBytes;
    void* p = nullptr;
    if (mapped_bytes_ > 0) {
      p = mremap(data_, mapped_bytes_, mapped, MREMAP_MAYMOVE);
      if (p == MAP_FAILED) throw std::bad_alloc();
    } else {
      p = mmap(nullptr, mapped, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
      if (p == MAP_FAILED) throw std::bad_alloc();
      if (size_ > 0) std::memcpy(p, data_, size_ * sizeof(T));
      ::operator delete(data_);
    }
    madvise(p, mapped, MADV_HUGEPAGE);  // advice only: ordinary pages if refused
    data_ = static_cast<T*>(p);
    mapped_bytes_ = mapped;
    capacity_ = mapped / sizeof(T);
  }

 private:
  void Release() {
    if (mapped_bytes_ > 0) {
      munmap(data_, mapped_bytes_);
    } else {
      ::operator delete(data_);
    }
    data_ = nullptr;
    size_ = capacity_ = mapped_bytes_ = 0;
  }

  T* data_ = nullptr;
  size_t size_ = 0, capacity_ = 0;
  size_t mapped_bytes_ = 0;  ///< the mapping's length, or 0 while in operator new memory
};

}  // namespace momenta
