#pragma once
// Every allocation through operator new is counted while `counting` is set: the numeric phase
// and the physics step must allocate nothing after their first call. Include from exactly one
// source file per test executable: it replaces the global operator new and delete.
#include <cstdint>
#include <cstdlib>
#include <new>

namespace {
bool counting = false;
int64_t allocations = 0;
}  // namespace

// The whole family of replaceable operator new/delete (plain, array, nothrow, sized) is replaced
// together, all on malloc/free: replacing only some leaves the others to the sanitizer's
// allocator and memory crosses between the two (AddressSanitizer's alloc-dealloc-mismatch).
// GCC warns that free() receives memory from operator new; here operator new is malloc.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
namespace {
void* counted_malloc(std::size_t size) noexcept {
  if (counting) ++allocations;
  return std::malloc(size ? size : 1);
}
}  // namespace
void* operator new(std::size_t size) {
  if (void* p = counted_malloc(size)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t size) { return operator new(size); }
void* operator new(std::size_t size, const std::nothrow_t&) noexcept { return counted_malloc(size); }
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept { return counted_malloc(size); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }
#pragma GCC diagnostic pop
